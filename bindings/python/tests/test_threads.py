"""Long work releases the GIL: while one thread is inside ``probelab.eval``, another Python
thread keeps running; results from threads equal the sequential ones."""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor

import probelab
from conftest import CC0_MAPS

SLOW = ["zh3_solved_channel", "sg_nnls", "ambient_dice"]


def test_another_python_thread_runs_during_eval():
    done = threading.Event()
    result = {}

    def work():
        result["rows"] = probelab.eval(str(CC0_MAPS[0]), SLOW, resolution=(512, 256))
        done.set()

    ticks = 0
    worker = threading.Thread(target=work)
    start = time.perf_counter()
    worker.start()
    # Python code that needs the GIL: with the GIL held by eval it could not run until eval ends.
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    elapsed = time.perf_counter() - start
    assert len(result["rows"]) == len(SLOW)
    # Each tick takes about 1 ms; a held GIL would allow a handful at most (at the start and the end).
    assert elapsed > 0.05, f"eval took {elapsed:.3f} s: too short to tell; make the work longer"
    assert ticks > 20, f"only {ticks} ticks of another thread in {elapsed:.3f} s: the GIL was held"


def test_threads_give_the_sequential_rows():
    paths = [str(p) for p in CC0_MAPS[:4]]
    sequential = [probelab.eval(p, ["sh2", "zh3_hallucinate"]) for p in paths]
    with ThreadPoolExecutor(max_workers=4) as pool:
        threaded = list(pool.map(lambda p: probelab.eval(p, ["sh2", "zh3_hallucinate"]), paths))
    assert threaded == sequential
