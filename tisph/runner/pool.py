"""Several runs at once, each in a worker process of its own: a validation table, a seed ensemble.

A step's parallel loops are short at a few thousand particles, and Taichi's CPU threads scale
poorly on them (two threads 1.2-1.3x one, docs/performance.md), so a set of such runs finishes
sooner as one-thread runs side by side than as one many-thread run after another: two dam breaks
of 8,050 particles on two cores took 0.67 of the time that way. A large run's loops share out
well: the pipeline case of 47,931 particles on one thread beside another run stepped at half its
rate alone on two, so runs of WIDE particles or more go one at a time on every core
(docs/performance.md, "Runs side by side").
"""

import concurrent.futures as cf
import multiprocessing
import os
import signal
import threading


def plan(jobs, runs, cores=None):
    """(worker processes, Taichi CPU threads each) for `runs` runs: `jobs` workers (0: one a
    core), never more than the runs, and the cores shared out among them."""
    cores = cores or os.cpu_count() or 1
    n = max(1, min(jobs or cores, runs))
    return n, max(1, cores // n)


WIDE = 20000  # particles: a run this large goes alone, on every core


def stages(tasks, sizes, jobs, cores=None):
    """[(tasks, jobs, threads), ...] to run one after another: the runs of WIDE particles or more
    (sizes: each task's particles, 0 if unknown) alone on every core, then the rest `jobs` at a
    time (plan). jobs 1: every run alone on every core."""
    cores = cores or os.cpu_count() or 1
    wide = [t for t, n in zip(tasks, sizes) if n >= WIDE or jobs == 1]
    rest = [t for t, n in zip(tasks, sizes) if not (n >= WIDE or jobs == 1)]
    out = [(wide, 1, cores)] if wide else []
    if rest:
        out.append((rest, *plan(jobs, len(rest), cores)))
    return out


def die_with_parent(sig, parent=None):
    """This process is sent `sig` when its parent dies (kill, kill -9) instead of running on
    alone (Linux prctl PR_SET_PDEATHSIG; elsewhere nothing). parent: its pid, where known: a
    parent that died before the prctl took hold cannot send it, so the process exits now."""
    try:
        import ctypes

        ctypes.CDLL(None).prctl(1, sig)
    except (OSError, AttributeError):
        pass
    if parent is not None and os.getppid() != parent:
        os._exit(1)


def _start(threads):
    # read by runtime.init, before the worker's first run initialises Taichi
    os.environ["TISPH_THREADS"] = str(threads)
    # SIGTERM stops a worker's run as a kill of a plain run does (its files complete)
    die_with_parent(signal.SIGTERM)


def _term(signum, frame):
    raise SystemExit(143)


def run_all(tasks, jobs, threads, done):
    """tasks: [(key, fn, args)], in the order to start them (the longest first keeps the last
    worker from finishing alone). Calls done(key, result, error) in this process as each ends;
    error is the exception a run raised, else None. One job runs them here, one after another.
    An interrupt (a run that raises SystemExit, Ctrl-C) cancels the runs not started and stops."""
    if jobs <= 1:
        for key, fn, args in tasks:
            try:
                r, e = fn(*args), None
            except Exception as exc:  # noqa: BLE001 - reported to done, the others go on
                r, e = None, exc
            done(key, r, e)
        return
    ctx = multiprocessing.get_context("spawn")  # a fresh interpreter: no Taichi state forked
    ex = cf.ProcessPoolExecutor(jobs, mp_context=ctx, initializer=_start, initargs=(threads,))
    # a kill of this process stops the workers' runs too (below), not only this one
    old = signal.signal(signal.SIGTERM, _term) if threading.current_thread() is threading.main_thread() else None
    try:
        futures = {ex.submit(fn, *args): key for key, fn, args in tasks}
        for f in cf.as_completed(futures):
            try:
                r, e = f.result(), None
            except Exception as exc:  # noqa: BLE001
                r, e = None, exc
            done(futures[f], r, e)
    except BaseException:
        for p in list(getattr(ex, "_processes", {}).values()):  # each running run stops as a killed run does
            p.terminate()
        raise
    finally:
        ex.shutdown(wait=True, cancel_futures=True)
        if old is not None:
            signal.signal(signal.SIGTERM, old)
