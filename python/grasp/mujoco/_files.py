"""The files of ``grasp.mujoco``, through the project's one file policy (``grasp-io``, the same
Rust code as the CLI's and ``grasp.transfer``'s, reached through ``grasp._native``).

Outputs are written all or nothing: every target checked before the work (a folder, a
symbolic link, a dangling one too, a device, a FIFO or a socket refused even with
``overwrite``/``--force``; an existing file kept without it; a target that is one of the run's
inputs, by device and inode, or named twice refused; the folder must exist; a target another
run is writing refused, naming its process), then locked, each written to an exclusive hidden
temporary file beside it (``O_CREAT|O_EXCL|O_NOFOLLOW``), and all moved into place at the end
without replacing anything that appeared meanwhile (with ``overwrite``, a regular file only).
A failure removes the temporary files and leaves existing files untouched.

Inputs are regular files (never a FIFO, a device such as ``/dev/zero`` or a folder) within
their kind's size limit, checked before and after opening, read with a bound.
"""

import os

from .. import _native

# How messages of the output policy name its force option here (the API and the command).
FORCE_NAME = "overwrite=True (--force)"


def _paths(paths):
    return [os.fspath(p) for p in paths]


def check_targets(paths, overwrite=False, inputs=()):
    """Refuses targets that cannot be written (their locks tried too); returns their paths."""
    paths = _paths(paths)
    _native._check_outputs(paths, overwrite=overwrite, inputs=_paths(inputs), force_name=FORCE_NAME)
    return paths


def write_all(outputs, overwrite=False, inputs=()):
    """Writes {path: text or bytes} all or nothing; returns the paths written."""
    contents = [(os.fspath(p), c if isinstance(c, bytes) else c.encode("utf-8")) for p, c in outputs.items()]
    _native._write_outputs(contents, overwrite=overwrite, inputs=_paths(inputs), force_name=FORCE_NAME)
    return [p for p, _ in contents]


def read_input(path, kind, error):
    """The bytes of the input file ``path`` of ``kind`` (``"mujoco_state"``,
    ``"mujoco_rollout"``, ``"material_map"``); a refusal is raised as ``error(message, fix)``."""
    try:
        return _native._read_input(os.fspath(path), kind)
    except OSError as e:
        raise error(getattr(e, "message", str(e)), getattr(e, "fix", "")) from None


def check_input(path, kind, error):
    """Checks the input file ``path`` of ``kind`` (regular, within its limit) without reading
    it, for a file another library reads by path; a refusal is raised as ``error(message, fix)``."""
    try:
        _native._check_input(os.fspath(path), kind)
    except OSError as e:
        raise error(getattr(e, "message", str(e)), getattr(e, "fix", "")) from None
