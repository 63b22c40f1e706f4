"""Runs as Python sees them: the progress callback (its reports, False to stop, an exception that
stops the run and surfaces, a bar with tqdm), Ctrl-C (KeyboardInterrupt within a fraction of a
second, in a child process so that the signal cannot reach pytest), the GIL released during the
run (another thread runs, two runs at once), and a callback that optimizes again."""

import json
import math
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import quadopt
from helpers import ROOT, bits, bumpy, jittered_grid


@pytest.fixture(scope="module")
def medium():
    """Some 40,000 quads, folded here and there: a run of about half a second."""
    return jittered_grid(200, 200, jitter=0.45, seed=4)


def test_progress_reports_every_sweep_and_changes_nothing(medium):
    points, faces = medium
    seen = []
    r = quadopt.optimize(points, faces, progress=lambda p: seen.append(p))
    assert seen and all(isinstance(p, quadopt.Progress) for p in seen)
    assert len({p.max_iterations for p in seen}) == 1 and all(p.pass_ == 1 and p.passes == 1 for p in seen)
    sweeps = [p.iteration for p in seen if p.iteration > 0]
    assert sweeps == sorted(sweeps) and sweeps[-1] >= r.report["iterations"]
    assert any(math.isfinite(p.energy) for p in seen)
    assert "Progress(iteration=" in repr(seen[-1])
    plain = quadopt.optimize(points, faces)
    np.testing.assert_array_equal(bits(r.points), bits(plain.points))
    capped = []
    quadopt.optimize(points, faces, max_iterations=3, progress=capped.append)
    assert {p.max_iterations for p in capped} == {3}


def test_progress_on_a_surface():
    points, faces = jittered_grid(20, 20, jitter=0.3, seed=2)
    seen = []
    r = quadopt.optimize(bumpy(points), faces, progress=seen.append)
    assert seen and r.report["surface"] is True
    assert len({p.max_iterations for p in seen}) == 1


def test_returning_false_cancels(medium):
    points, faces = medium
    before = points.copy()
    calls = []

    def stop_at_third(p):
        calls.append(p)
        return len(calls) < 3

    with pytest.raises(quadopt.CancelledError, match="cancelled by the progress callback"):
        quadopt.optimize(points, faces, progress=stop_at_third)
    assert len(calls) == 3
    assert points.tobytes() == before.tobytes()
    # True and None go on; only False stops.
    quadopt.optimize(points, faces, max_iterations=4, progress=lambda p: True)
    quadopt.optimize(points, faces, max_iterations=4, progress=lambda p: 0)


@pytest.mark.parametrize("threads", [None, 2])
def test_an_exception_in_the_callback_surfaces(medium, threads):
    points, faces = medium
    calls = []

    class Boom(Exception):
        pass

    def explode(p):
        calls.append(p)
        if len(calls) == 2:
            raise Boom("from the callback")

    with pytest.raises(Boom, match="from the callback") as info:
        quadopt.optimize(points, faces, threads=threads, progress=explode)
    assert len(calls) == 2, "the run went on after the exception"
    assert any(frame.name == "explode" for frame in info.traceback)
    # Nothing crashed: the next run is the plain one.
    assert quadopt.optimize(points, faces, threads=threads).report["output"]["inverted"] == 0
    with pytest.raises(KeyboardInterrupt):
        quadopt.optimize(points, faces, progress=lambda p: (_ for _ in ()).throw(KeyboardInterrupt))


@pytest.mark.parametrize("threads", [None, 1, 2])
def test_the_callback_runs_on_the_calling_thread(threads):
    points, faces = jittered_grid(30, 30, jitter=0.4, seed=8)
    idents = set()
    quadopt.optimize(points, faces, threads=threads, progress=lambda p: idents.add(threading.get_ident()))
    assert idents == {threading.get_ident()}


def test_a_callback_may_optimize_again():
    points, faces = jittered_grid(15, 15, jitter=0.4, seed=9)
    inner = []

    def nested(p):
        if len(inner) < 3:
            inner.append(quadopt.optimize(points, faces, max_iterations=2))

    outer = quadopt.optimize(points, faces, progress=nested)
    assert len(inner) == 3 and outer.report["output"]["inverted"] == 0
    np.testing.assert_array_equal(bits(outer.points), bits(quadopt.optimize(points, faces).points))


def test_progress_true_draws_a_tqdm_bar(medium, capsys):
    pytest.importorskip("tqdm")
    points, faces = medium
    r = quadopt.optimize(points, faces, progress=True)
    err = capsys.readouterr().err
    assert "quadopt" in err and "sweep" in err
    np.testing.assert_array_equal(bits(r.points), bits(quadopt.optimize(points, faces).points))


def test_progress_true_without_tqdm_draws_nothing(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    points, faces = jittered_grid(10, 10, jitter=0.3, seed=1)
    quadopt.optimize(points, faces, progress=True)
    assert capsys.readouterr().err == ""


def test_another_thread_runs_during_a_run(medium):
    points, faces = medium
    ticks = []
    done = threading.Event()

    def heartbeat():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.002)

    t = threading.Thread(target=heartbeat)
    t.start()
    time.sleep(0.05)
    start = time.perf_counter()
    r = quadopt.optimize(points, faces)
    end = time.perf_counter()
    done.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    # Sleeping 2 ms a tick, the thread ticks every few ms if the GIL is free; held for the whole
    # run it could not tick at all.
    assert end - start > 0.1, "the run is too short to tell"
    assert len(during) > (end - start) / 0.02, f"{len(during)} ticks in a run of {end - start:.2f} s"
    assert r.report["output"]["inverted"] == 0


def test_two_runs_at_once_from_two_threads():
    meshes = [jittered_grid(60, 60, jitter=0.4, seed=s) for s in (1, 2)]
    alone = [quadopt.optimize(p, f) for p, f in meshes]
    together = [None, None]

    def run(k):
        together[k] = quadopt.optimize(*meshes[k], threads=1 + k)

    threads = [threading.Thread(target=run, args=(k,)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(alone, together):
        np.testing.assert_array_equal(bits(a.points), bits(b.points))


INTERRUPT = textwrap.dedent("""
    import json, os, signal, sys, threading, time
    sys.path.insert(0, sys.argv[1])
    import numpy as np, quadopt
    from helpers import jittered_grid
    points, faces = jittered_grid(400, 400, jitter=0.45, seed=3)
    threads = None if sys.argv[2] == "default" else int(sys.argv[2])
    sent = []
    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)
    before = points.copy()
    start = time.perf_counter()
    threading.Timer(0.6, interrupt).start()
    try:
        quadopt.optimize(points, faces, threads=threads, effort="best")
        out = {"interrupted": False, "seconds": time.perf_counter() - start}
    except KeyboardInterrupt:
        out = {"interrupted": True, "latency": time.perf_counter() - sent[0]}
    out["untouched"] = points.tobytes() == before.tobytes()
    small = jittered_grid(20, 20, jitter=0.4, seed=5)
    out["again"] = quadopt.optimize(*small).points.tolist() == quadopt.optimize(*small).points.tolist()
    print(json.dumps(out))
""")


@pytest.mark.parametrize("threads", ["default", "2"])
def test_ctrl_c_cancels_within_a_fraction_of_a_second(tmp_path, threads):
    script = tmp_path / "interrupt.py"
    script.write_text(INTERRUPT)
    r = subprocess.run([sys.executable, str(script), str(ROOT / "python" / "tests"), threads],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["interrupted"], f"the run ended ({out}) before the signal: too short a run"
    assert out["latency"] < 0.5, f"KeyboardInterrupt came {out['latency']:.3f} s after SIGINT"
    assert out["untouched"] and out["again"]
