"""The GIL is released while the library solves: another Python thread keeps running."""

import threading
import time

import grasp


def test_another_thread_runs_while_a_solve_is_in_progress(cube_a_dict):
    for f in cube_a_dict["fingers"]:
        f["patch"]["grid"] = [16, 16]  # about 0.2 s per solve on 2 cores
    scene = grasp.Scene(cube_a_dict)
    t0 = time.perf_counter()
    grasp.solve(scene)
    alone_s = time.perf_counter() - t0
    done = threading.Event()
    worker = threading.Thread(target=lambda: (grasp.solve(scene), done.set()))
    ticks = []
    worker.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
    worker.join()
    gaps = [b - a for a, b in zip(ticks, ticks[1:])]
    # Holding the GIL would freeze this loop for the whole solve (one gap about alone_s);
    # released, the loop only yields at the interpreter's switch interval (5 ms).
    assert len(ticks) > 100
    assert max(gaps) < 0.5 * alone_s, (max(gaps), alone_s)
