"""Arrays of the .npz and .npy inputs (state files, rollouts), read from their bytes: no pickles;
an archive's unpacked size within its file's limit (a small compressed .npz may unpack to far
more); and any failure of NumPy's reader on a corrupt or truncated file (``BadZipFile``,
``EOFError``, ``ValueError``...) said as ``error(message, fix)``, naming the file."""

import io

import numpy as np

MIB = 1 << 20


def reason(e):
    return f"{type(e).__name__}: {e}" if str(e) else type(e).__name__


def unpack(raw, src, what, error, fix):
    """What ``np.load`` makes of ``raw`` (an ndarray or an NpzFile), or ``error``."""
    try:
        return np.load(io.BytesIO(raw), allow_pickle=False)
    except Exception as e:  # noqa: BLE001 (NumPy's and zipfile's errors, whatever the file holds)
        raise error(f"{src} is not {what} ({reason(e)})", fix) from None


def load_npz(raw, src, what, limit_bytes, error, fix):
    """{name: array} of the .npz bytes ``raw`` of the input ``src`` (``what`` it should be:
    "a rollout written by ..."), unpacking to at most ``limit_bytes``."""
    z = unpack(raw, src, what, error, fix)
    if not isinstance(z, np.lib.npyio.NpzFile):
        raise error(f"{src} is not {what} (it holds one array, an .npy, not an .npz archive of named arrays)", fix)
    with z:
        size = sum(info.file_size for info in z.zip.infolist())
        if size > limit_bytes:
            raise error(f"{src} unpacks to {size} bytes, more than the {limit_bytes // MIB} MiB its file may have",
                        f"give a smaller .npz ({what})")
        try:
            return {k: np.array(z[k]) for k in z.files}
        except Exception as e:  # noqa: BLE001
            raise error(f"{src} is not {what} ({reason(e)})", fix) from None


def load_npy(raw, src, what, error, fix):
    """The array of the .npy bytes ``raw`` of the input ``src``."""
    a = unpack(raw, src, what, error, fix)
    if not isinstance(a, np.ndarray):
        a.close()
        raise error(f"{src} is not {what} (it is an .npz archive, not one .npy array)", fix)
    return a
