"""``python -m grasp.mujoco``: a grasp or a hand-off from MuJoCo, from the shell.

    python -m grasp.mujoco scene MODEL.xml --object BODY [--keyframe K | --qpos FILE]
        --materials MAP.json --out SCENE.json [--report R.json] [--rrd R.rrd]
    python -m grasp.mujoco scene ROBOT.urdf --object LINK --qpos FILE [--mesh-dir DIR]
        [--no-fuse-static] [--balance-inertia] --materials MAP.json --out SCENE.json
    python -m grasp.mujoco handoff MODEL.xml --object BODY
        (--rollout ROLLOUT.npz | --controller MODULE:FN --steps N) --materials MAP.json
        --out PREFIX [--mcap F] [--rrd F] [--csv F] [--margins]

Exit codes: 0 done; 1 bad input (a named error, nothing written); 2 the elastic model found no
equilibrium for the scene, or at a step of the hand-off where MuJoCo held the object (the files
are written); 128 + the signal (130, 143, 129) after SIGINT, SIGTERM or SIGHUP, as the CLI: the
run stops, its temporary files and folders and its output locks are removed, existing files are
untouched (a signal that arrives while the native library computes takes effect when that call
returns, before anything is moved into place).
"""

import argparse
import json
import os
import signal
import sys

from ._errors import Interrupted, MujocoError
from ._progress import terminal_bar

PROG = "python -m grasp.mujoco"


class Parser(argparse.ArgumentParser):
    """Usage errors exit 1, as every bad input of the project's commands."""

    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(1, f"{self.prog}: error: {message}\n")


def common(p):
    p.add_argument("model", help="MuJoCo model: MJCF .xml, URDF .urdf (MuJoCo compiles it) or binary .mjb")
    p.add_argument("--object", required=True, help="the grasped object's body (name)")
    p.add_argument("--materials", help="JSON map {geom or body name: material}; unnamed geoms get rubber (warned)")
    p.add_argument("--grid", nargs=2, type=int, metavar=("NX", "NY"), help="patch elements per finger (default 9 9)")
    p.add_argument("--margin", type=float, metavar="M", help="flat pairs: patch margin around MuJoCo's points, m (default 0)")
    p.add_argument("--patch-size", nargs=2, type=float, metavar=("A", "B"), help="every patch's sides, m (overrides)")
    p.add_argument("--sensor", metavar="JSON|FILE",
                   help="a tactile sensor in every pad: fingers[i].sensor as JSON text or a .json file "
                        "(taxels, markers, gel; docs/guide/tactile.md)")
    p.add_argument("--mesh-dir", metavar="DIR",
                   help="URDF: the folder of its meshes, each looked up there by its bare file name (package:// and "
                        "folders stripped)")
    p.add_argument("--fuse-static", action=argparse.BooleanOptionalAction, default=None,
                   help="URDF: fuse links on fixed joints into their parents (MuJoCo's default for URDF); "
                        "--no-fuse-static keeps them as bodies")
    p.add_argument("--balance-inertia", action="store_true",
                   help="URDF: let MuJoCo balance link inertias that break the triangle inequality")
    p.add_argument("--force", action="store_true", help="replace existing output files")
    p.add_argument("--quiet", action="store_true", help="no progress line (drawn on a terminal only)")


def parser():
    top = Parser(prog=PROG, description="A grasp or a hand-off from MuJoCo, solved by the elastic contact model.")
    sub = top.add_subparsers(dest="command", required=True, parser_class=Parser)
    s = sub.add_parser("scene", help="a grasp scene from one MuJoCo state, and MuJoCo's forces beside this project's")
    common(s)
    state = s.add_mutually_exclusive_group()
    state.add_argument("--keyframe", help="keyframe name or index")
    state.add_argument("--qpos", help="state file: qpos numbers (.txt, .npy) or .npz/.json with qpos, qvel, ctrl, act")
    s.add_argument("--out", required=True, help="scene file to write (JSON)")
    s.add_argument("--control", choices=["held", "mujoco-force", "mujoco-servo"], default="mujoco-force",
                   help="fingers position-held, force-controlled at MuJoCo's normal force (default), or on their "
                        "servos (position actuators' kp as mounts)")
    s.add_argument("--model", dest="contact_model", choices=["energy", "coulomb"], default="energy")
    s.add_argument("--report", help="side-by-side report to write (JSON)")
    s.add_argument("--rrd", help="Rerun recording of the scene with both force sets as arrows")
    s.add_argument("--no-margin", action="store_true", help="skip the disturbance margin (seconds on fine grids)")
    s.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    h = sub.add_parser("handoff", help="a scene plus a load schedule from a MuJoCo rollout, replayed by grasp.transfer")
    common(h)
    src = h.add_mutually_exclusive_group(required=True)
    src.add_argument("--rollout", help=".npz of time, qpos, qvel (and ctrl, act, qacc_warmstart, mocap_*) per step")
    src.add_argument("--controller", help="MODULE:FN (a module or a .py file): FN(model, data) sets data.ctrl")
    h.add_argument("--steps", type=int, help="MuJoCo steps to run the controller for")
    h.add_argument("--every", type=int, default=1, help="record every K-th step (default 1; first and last kept)")
    start = h.add_mutually_exclusive_group()
    start.add_argument("--keyframe", help="the controller's start state: keyframe name or index")
    start.add_argument("--qpos", help="the controller's start state: a state file")
    h.add_argument("--out", required=True, metavar="PREFIX", help="writes PREFIX.json, PREFIX.schedule.json, PREFIX.csv")
    h.add_argument("--model", dest="contact_model", choices=["energy", "coulomb"], default="coulomb")
    h.add_argument("--save-rollout", help="also write the rollout (.npz, readable by --rollout)")
    h.add_argument("--no-replay", action="store_true", help="write the scene and schedule only")
    h.add_argument("--mcap", help="replay's MCAP log")
    h.add_argument("--rrd", help="replay's Rerun recording, with MuJoCo's forces beside this project's")
    h.add_argument("--csv", help="replay's CSV history")
    h.add_argument("--margins", action="store_true", help="every step's smallest disturbance margin (slow)")
    h.add_argument("--threshold", type=float, metavar="N", help="flag steps whose smallest margin is below N newtons (implies --margins)")
    return top


def patch_of(args):
    p = {}
    if args.grid:
        p["grid"] = list(args.grid)
    if args.margin is not None:
        p["margin_m"] = args.margin
    if args.patch_size:
        p["size"] = list(args.patch_size)
    return p


def sensor_of(args):
    """``--sensor``: None, JSON text (starting with ``{``) or a JSON file's path, as a dict."""
    text = args.sensor
    if text is None:
        return None
    where = "--sensor"
    if not text.lstrip().startswith("{"):
        where = f"--sensor {text}"
        try:
            with open(text, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise MujocoError(f"{where}: cannot read it ({e.strerror})",
                              "give the sensor as JSON text ({...}) or the path of a readable .json file") from None
    try:
        return json.loads(text)
    except ValueError as e:
        raise MujocoError(f"{where} is not JSON ({e})", "give the sensor as a JSON object, e.g. "
                          '\'{"taxels": {"count": [4, 4], "pitch_m": 0.002, "size_m": 0.002, "depth_m": 0.001}}\'') from None


def inputs_of(args):
    sensor_file = args.sensor if args.sensor and not args.sensor.lstrip().startswith("{") else None
    return [x for x in (args.model, args.materials, getattr(args, "qpos", None), getattr(args, "rollout", None),
                        sensor_file) if x]


def load_model_of(args):
    """The model of ``args.model`` with the URDF options; each warning printed as ``warning: ...``."""
    import warnings

    from ._state import load_model

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = load_model(args.model, mesh_dir=args.mesh_dir, fuse_static=args.fuse_static,
                           balance_inertia=args.balance_inertia)
    for w in caught:
        print(f"warning: {w.message}", file=sys.stderr)
    return model


def run_scene(args):
    from ._files import check_targets
    from ._report import compare
    from ._scene import scene_from
    from ._state import load_state

    outs = [args.out] + [p for p in (args.report, args.rrd) if p]
    check_targets(outs, args.force, inputs_of(args))
    if args.rrd:
        from ._rerun import require_rerun

        require_rerun()
    model = load_model_of(args)
    data = load_state(model, keyframe=args.keyframe, qpos=args.qpos)
    state = f"keyframe {args.keyframe}" if args.keyframe else (f"state {args.qpos}" if args.qpos else "the initial state")
    g = scene_from(model, data, args.object, materials=args.materials, patch=patch_of(args), control=args.control,
                   contact_model=args.contact_model, sensor=sensor_of(args),
                   description=(f"From MuJoCo: body '{args.object}' of {os.path.basename(args.model)} at {state} "
                                f"(python -m grasp.mujoco scene); fingers {args.control}."),
                   mesh_name=f"{os.path.splitext(os.path.basename(args.out))[0]}.{args.object}.obj")
    for w in g.warnings:
        print(f"warning: {w}", file=sys.stderr)
    report = compare(g, margins=not args.no_margin)
    report.write(json_path=args.report, rrd=args.rrd, overwrite=args.force, inputs=inputs_of(args),
                 also=g.outputs(args.out))
    print(report.table(markdown=args.markdown))
    print("wrote " + ", ".join(outs))
    return 0 if report.grasp_holds else 2


def run_handoff(args):
    from ._files import check_targets
    from ._controller import simulate
    from ._handoff import check_threshold, schedule_from_rollout
    from ._patch import patch_options, sensor_option
    from ._state import Rollout, load_state

    if args.controller and args.steps is None:
        raise MujocoError("--controller needs --steps", "give the number of MuJoCo steps to run, e.g. --steps 1600")
    if args.rollout and (args.steps is not None or args.keyframe or args.qpos):
        raise MujocoError("--steps, --keyframe and --qpos go with --controller", "leave them out with --rollout")
    prefix = args.out
    replay_outs = [p for p in (args.mcap, args.rrd, args.csv) if p]
    if args.no_replay and (replay_outs or args.margins):
        raise MujocoError("--no-replay with replay outputs", "leave out --no-replay, or --mcap/--rrd/--csv/--margins")
    # Checked before the (long) simulation, as the controller's steps are.
    patch_options(patch_of(args))
    sensor_option(sensor_of(args))
    check_threshold(args.threshold)
    if args.rrd:
        from ._rerun import require_rerun

        require_rerun()
    model = load_model_of(args)
    if args.rollout:
        rollout = Rollout.load(args.rollout, model)
    else:
        data = load_state(model, keyframe=args.keyframe, qpos=args.qpos)
        # The targets are checked before the (long) simulation.
        check_targets(replay_outs + [f"{prefix}.json", f"{prefix}.schedule.json", f"{prefix}.csv"]
                      + ([args.save_rollout] if args.save_rollout else []), args.force, inputs_of(args))
        rollout = simulate(model, data, args.controller, args.steps, args.every,
                           progress=terminal_bar("mujoco steps", args.quiet))
    h = schedule_from_rollout(model, rollout, args.object, materials=args.materials, patch=patch_of(args),
                              contact_model=args.contact_model, sensor=sensor_of(args))
    for w in h.warnings:
        print(f"warning: {w}", file=sys.stderr)
    outs = h.outputs(prefix)
    if args.save_rollout:
        import io

        buf = io.BytesIO()
        import numpy as np

        np.savez(buf, **{k: getattr(rollout, k) for k in ("time", "qpos", "qvel", "ctrl", "act", "qacc_warmstart",
                                                          "mocap_pos", "mocap_quat")})
        outs[args.save_rollout] = buf.getvalue()
    if args.no_replay:
        from ._files import write_all

        h.scene  # validated before anything is written
        write_all(outs, args.force, inputs_of(args))
        print(f"{len(h.times_s)} steps, fingers {', '.join(h.finger_names)}")
        print("wrote " + ", ".join(outs))
        return 0
    replay = h.replay(mcap=args.mcap, rrd=args.rrd, csv=args.csv, margins=args.margins or args.threshold is not None,
                      threshold_n=args.threshold,
                      overwrite=args.force, inputs=inputs_of(args), also=outs,
                      progress=terminal_bar("replayed steps", args.quiet))
    print(replay.summary_text())
    print("wrote " + ", ".join(list(outs) + replay_outs))
    # A discrepancy is a step where MuJoCo held the object and the elastic model found no
    # equilibrium (steps where MuJoCo did not hold either are reported, not failures).
    return 2 if any(why in ("no_equilibrium", "no_convergence") for _, _, why in replay.flagged_steps) else 0


CLEANUP_SIGNALS = tuple(getattr(signal, n) for n in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, n))


def on_signal(signum, frame):
    for s in CLEANUP_SIGNALS:  # one unwinding: a second signal does not cut the cleanup short
        signal.signal(s, signal.SIG_IGN)
    raise Interrupted(signum)


def install_signal_cleanup():
    """SIGINT, SIGTERM and SIGHUP end the run cleanly (see the module documentation)."""
    for s in CLEANUP_SIGNALS:
        signal.signal(s, on_signal)


def main(argv=None):
    args = parser().parse_args(argv)
    import grasp

    try:
        return run_scene(args) if args.command == "scene" else run_handoff(args)
    except Interrupted as e:
        print("interrupted: temporary files removed; existing files are untouched", file=sys.stderr)
        return 128 + e.signum
    except (MujocoError, grasp.SceneError, grasp.ScheduleError, grasp.GraspError, OSError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        problems = getattr(e, "problems", None)
        for p in problems or []:
            print(f"  {p['path']}: {p['message']}; fix: {p['fix']}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    install_signal_cleanup()
    sys.exit(main())
