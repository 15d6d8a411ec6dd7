"""The errors of ``grasp.mujoco``: each names what was wrong and how to fix it.

Every error is raised before anything is written (outputs are written last, each to a
temporary file moved into place only when all of them are ready).
"""

INSTALL_COMMAND = "pip install 'mujoco==4.0.0'"
EXTRA_COMMAND = "pip install '.[mujoco]'"


class MujocoError(ValueError):
    """Base of the errors of ``grasp.mujoco``; ``fix`` says what to do."""

    def __init__(self, message: str, fix: str = ""):
        self.message = message
        self.fix = fix
        super().__init__(f"{message}; fix: {fix}" if fix else message)


class MujocoNotInstalled(MujocoError, ImportError):
    """The ``mujoco`` package cannot be imported."""

    def __init__(self, cause: str = ""):
        detail = f" ({cause})" if cause else ""
        super().__init__(
            f"MuJoCo is not installed: the Python package 'mujoco' cannot be imported{detail}",
            f"install it with `{INSTALL_COMMAND}` (or, from the repository root, `{EXTRA_COMMAND}`)",
        )


class ModelLoadError(MujocoError):
    """The MuJoCo model (MJCF or binary) does not load."""


class StateError(MujocoError):
    """The state (keyframe, qpos file, rollout) does not load into the model."""


class UnknownBodyError(MujocoError):
    """The object body is not a body of the model, or not one that can be the grasped object
    (the world; a body fixed, welded or jointed other than free; a mocap body; no mass)."""


class MaterialMapError(MujocoError):
    """The material map names a geom or body the model does not have, or is malformed."""


class NoContactError(MujocoError):
    """The object body touches nothing at the state (or through the whole rollout)."""


class ContactGeometryError(MujocoError):
    """A contact whose geometry this project cannot represent (e.g. crossed cylinders at an angle)."""


class ControllerError(MujocoError):
    """The controller ``MODULE:FN`` cannot be imported, fails, or calls ``sys.exit``."""


class Interrupted(BaseException):
    """A SIGINT, SIGTERM or SIGHUP (``python -m grasp.mujoco``'s handlers raise it; a
    controller's errors let it pass, as ``KeyboardInterrupt``): unwinds the run, so every
    ``with`` and ``finally`` on the way removes what it made (scratch folders; the native
    library's temporary and lock files are removed when their owners are dropped)."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def require_mujoco():
    """The ``mujoco`` module, or :class:`MujocoNotInstalled` with the install command."""
    try:
        import mujoco  # noqa: PLC0415 (optional dependency, imported on use)
    except ImportError as e:
        raise MujocoNotInstalled(str(e)) from None
    return mujoco
