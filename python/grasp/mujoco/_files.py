"""Outputs written all or nothing, as the project's CLI writes them: every target checked
first (no overwrite without ``overwrite``/``--force``, no folder, no name twice, the folder must
exist), each written to a temporary file beside it, all moved into place at the end; a failure
removes the temporaries and leaves existing files untouched."""

import os
import secrets


def check_targets(paths, overwrite=False, inputs=()):
    """Refuses targets that cannot be written; returns their absolute paths."""
    seen = set()
    real_inputs = {os.path.realpath(p) for p in inputs}
    out = []
    for p in paths:
        a = os.path.abspath(os.fspath(p))
        if a in seen:
            raise ValueError(f"the same file is named twice as an output: {p}")
        seen.add(a)
        if os.path.realpath(a) in real_inputs:
            raise ValueError(f"{p} is an input; refusing to write over it")
        folder = os.path.dirname(a)
        if not os.path.isdir(folder):
            raise FileNotFoundError(f"cannot write {p}: the folder does not exist")
        if os.path.isdir(a) or os.path.islink(a):
            raise IsADirectoryError(f"cannot write {p}: it is a folder or a symbolic link")
        if os.path.exists(a) and not overwrite:
            raise FileExistsError(f"{p} exists; give overwrite=True (--force) to replace it")
        out.append(a)
    return out


def write_all(outputs, overwrite=False, inputs=()):
    """Writes {path: text or bytes} all or nothing; returns the paths written."""
    paths = check_targets(list(outputs), overwrite, inputs)
    temps = []
    try:
        for a, content in zip(paths, outputs.values()):
            tmp = os.path.join(os.path.dirname(a),
                               f".{os.path.basename(a)}.grasp-tmp-{os.getpid()}-{secrets.token_hex(4)}")
            temps.append(tmp)
            mode = "wb" if isinstance(content, bytes) else "w"
            with open(tmp, mode, **({} if mode == "wb" else {"encoding": "utf-8", "newline": ""})) as f:
                f.write(content)
        for tmp, a in zip(temps, paths):
            os.replace(tmp, a)
        temps = []
    finally:
        for tmp in temps:
            try:
                os.remove(tmp)
            except OSError:
                pass
    return [os.fspath(p) for p in outputs]


def temp_path_beside(target, suffix):
    """A fresh temporary path beside ``target`` (not created)."""
    a = os.path.abspath(os.fspath(target))
    return os.path.join(os.path.dirname(a),
                        f".{os.path.basename(a)}.grasp-tmp-{os.getpid()}-{secrets.token_hex(4)}{suffix}")
