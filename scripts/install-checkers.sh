#!/usr/bin/env bash
# Installs what the tests call besides Rust, in the virtualenv $HOME/.cache/grasp-venv:
# - the `rerun` CLI from rerun-sdk==0.36.3 (same version as the Rust SDK we write with), the
#   independent checker of our recordings and MCAP files;
# - pytest (the Python package's tests) and Ray (the distributed example, run on a local
#   runtime). NumPy comes with rerun-sdk;
# - foxglove-sdk (Foxglove's own message types, to check our foxglove.SceneUpdate messages) and
#   mcap (an independent MCAP reader);
# - mujoco (grasp.mujoco's optional dependency, pinned: its tests compare with MuJoCo's own numbers);
# - tamaas (the FFT boundary-element peer of `grasp bench`'s Hertz FFT cases, run through
#   scripts/peer-hertz.py; pinned, its times are compared with ours);
# - mypy (the type check of the package's stubs, tests/python/test_type_stubs.py);
# - mcap-ros2-support and rosbags (two independent ROS 2 decoders, without ROS, of the MCAP's ROS 2
#   profile: tests/python/test_ros2_mcap.py).
set -euo pipefail
venv="$HOME/.cache/grasp-venv"
want_rerun="0.36.3" want_pytest="9.2.0" want_ray="2.40.0" want_foxglove="0.30.3" want_mcap="1.6.0" want_mujoco="4.0.0" want_tamaas="2.9.0" want_mypy="1.13.0" want_mcap_ros2="0.6.0" want_rosbags="0.11.9"
if [ -x "$venv/bin/rerun" ] && CI=1 "$venv/bin/python" - "$want_rerun" "$want_pytest" "$want_ray" "$want_foxglove" "$want_mcap" "$want_mujoco" "$want_tamaas" "$want_mypy" "$want_mcap_ros2" "$want_rosbags" 2>/dev/null <<'PY'
import sys
from importlib.metadata import version
want = dict(zip(["rerun-sdk", "pytest", "ray", "foxglove-sdk", "mcap", "mujoco", "tamaas", "mypy", "mcap-ros2-support", "rosbags"], sys.argv[1:]))
sys.exit(0 if all(version(k) == v for k, v in want.items()) else 1)
PY
then
  exit 0
fi
[ -x "$venv/bin/pip" ] || python3 -m venv "$venv"
"$venv/bin/pip" install --quiet --disable-pip-version-check \
  "rerun-sdk==$want_rerun" "pytest==$want_pytest" "ray==$want_ray" \
  "foxglove-sdk==$want_foxglove" "mcap==$want_mcap" "mujoco==$want_mujoco" "tamaas==$want_tamaas" \
  "mypy==$want_mypy" "mcap-ros2-support==$want_mcap_ros2" "rosbags==$want_rosbags"
CI=1 "$venv/bin/rerun" --version
