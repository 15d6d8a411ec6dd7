"""A progress line on a terminal's standard error for the long runs of ``python -m grasp.mujoco``
(the simulation, the replay): the count, the elapsed time and an estimate of what is left;
nothing when standard error is not a terminal, or with ``--quiet``. Anything called as
``progress(done, total)`` serves in its place (``simulate``'s and ``HandoffSchedule.replay``'s
``progress=``; a ``tqdm`` bar's ``update`` wrapped, say)."""

import sys
import time

# Seconds between two redraws (the last one is always drawn).
REDRAW_S = 0.1


def terminal_bar(what, quiet=False, stream=None):
    """``progress(done, total)`` drawing ``what done/total (elapsed, eta)`` on ``stream``
    (standard error), or None when quiet or the stream is not a terminal."""
    stream = stream if stream is not None else sys.stderr
    if quiet or not stream.isatty():
        return None
    start = time.monotonic()
    drawn = [start - REDRAW_S]

    def show(done, total):
        now = time.monotonic()
        if done < total and now - drawn[0] < REDRAW_S:
            return
        drawn[0] = now
        elapsed = now - start
        eta = elapsed / done * (total - done) if done else 0.0
        stream.write(f"\r{what} {done}/{total} ({elapsed:.0f} s, eta {eta:.0f} s)")
        if done >= total:
            stream.write("\r\x1b[2K")
        stream.flush()

    return show
