"""The files an MJCF (or URDF) model names, checked as the model file itself is (a regular,
readable file within the model's size limit: never a FIFO, a device or a folder) before MuJoCo
opens any of them; MuJoCo opens them itself, and a FIFO would block it for ever.

Checked: every attribute whose name begins with ``file`` (``<mesh file>``, ``<texture file>``
and its six cube faces ``fileright`` ... ``fileback``, ``<hfield file>``, ``<skin file>``,
``<flexcomp file>``, a sub-model's ``<model file>``, URDF's ``<mesh filename>``), in the model
and in every file it includes (``<include file>`` and ``<model file>``, read in turn).

MuJoCo looks a relative name up in more than one folder (the model's folder joined with the
compiler's ``meshdir``, ``texturedir`` or ``assetdir``; the including file's folder; the bare
file name where the compiler strips paths, as for URDF), and the rules differ between versions,
so every place it may look is checked. A name found nowhere is left to MuJoCo, which names it.
"""

import os
import xml.etree.ElementTree as ET

from ._errors import ModelLoadError
from ._files import check_input, read_input

# The compiler's folders, relative to the model's folder (or absolute).
DIR_ATTRS = ("assetdir", "meshdir", "texturedir")
# Elements whose file is a model MuJoCo reads in turn (and so are its files).
MODEL_TAGS = ("include", "model")
KIND = "mujoco_model"


def tag_of(elem):
    return elem.tag.lower() if isinstance(elem.tag, str) else ""


def file_attrs(elem):
    """(attribute, file name) of each file an element names."""
    return [(k, v) for k, v in elem.attrib.items() if k.lower().startswith("file") and v.strip()]


def parse(path, named_by):
    """The XML tree of a model file (read through the input policy)."""
    raw = read_input(path, KIND, ModelLoadError)
    try:
        return ET.fromstring(raw)
    except ET.ParseError as e:
        who = "MuJoCo model" if named_by is None else f"{named_by}: the included file"
        raise ModelLoadError(f"{who} {path} is not well-formed XML ({e}), so the files it names cannot be checked",
                             f"fix the XML of {path}") from None


def places(name, bases, dirs):
    """Every existing path MuJoCo may open for the file ``name`` (an absolute one itself, and
    its bare name in the folders; as written, and without surrounding blanks)."""
    out = []
    names = dict.fromkeys([name, name.strip(), os.path.basename(name), os.path.basename(name.strip())])
    for base in bases:
        for d in dirs:
            for n in names:
                p = os.path.normpath(os.path.join(base, d, n))
                if p not in out and os.path.exists(p):
                    out.append(p)
    return out


def check_place(path, naming, tag, attr, name):
    """``path`` as the model file is checked; the refusal names the element that names it."""
    prefix = f"MuJoCo model {path} "

    def error(message, fix):
        what = f"which {message[len(prefix):]}" if message.startswith(prefix) else f"but {message}"
        return ModelLoadError(f'{naming}: <{tag} {attr}="{name}"> names {path}, {what}',
                              f'make {path} a regular, readable file, or name another in <{tag} {attr}="..."> '
                              f"of {naming}")

    check_input(path, KIND, error)


def is_xml(tag, name):
    """An included file is MJCF; a sub-model is read in turn when it is XML (MJCF or URDF)."""
    return tag == "include" or name.lower().endswith((".xml", ".urdf"))


def read_tree(path):
    """(names, dirs): (naming file, tag, attribute, name, folders) of every file the model and
    the files it includes name (included ones checked before they are read), and the
    compiler's folders."""
    model_dir = os.path.dirname(os.path.abspath(path))
    dirs, names, seen = {""}, [], set()
    todo = [(os.path.abspath(path), None)]
    while todo:
        p, named_by = todo.pop()
        if os.path.realpath(p) in seen:
            continue  # MuJoCo refuses a file included twice, naming it
        seen.add(os.path.realpath(p))
        for elem in parse(p, named_by).iter():
            tag = tag_of(elem)
            if tag == "compiler":
                dirs |= {elem.get(a) for a in DIR_ATTRS if elem.get(a)}
            for attr, name in file_attrs(elem):
                bases = [model_dir, os.path.dirname(p)]
                names.append((p, tag, attr, name, bases))
                found = places(name, bases, [""]) if tag in MODEL_TAGS else []
                for q in found:
                    check_place(q, p, tag, attr, name)
                if found and is_xml(tag, name):
                    todo.append((found[0], p))
    return names, sorted(dirs)


def check_model_files(path, extra_dirs=()):
    """Checks every file the MJCF or URDF model at ``path`` names, its includes recursively, in
    the compiler's folders and ``extra_dirs`` (absolute: a URDF's ``--mesh-dir``);
    ModelLoadError naming the element and the file otherwise."""
    names, dirs = read_tree(path)
    dirs = sorted(set(dirs) | set(extra_dirs))
    for p, tag, attr, name, bases in names:
        for q in places(name, bases, dirs):
            check_place(q, p, tag, attr, name)
