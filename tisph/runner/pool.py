"""Several runs at once, each in a worker process of its own: a validation table, a seed ensemble.

A step's parallel loops are short, and Taichi's CPU threads scale poorly on them (two threads
1.2-1.3x one, docs/performance.md), so a set of runs finishes sooner as one-thread runs side by
side than as one many-thread run after another: two dam breaks on two cores took 0.67 of the
time that way (docs/performance.md, "Runs side by side").
"""
import concurrent.futures as cf
import multiprocessing
import os


def plan(jobs, runs, cores=None):
    """(worker processes, Taichi CPU threads each) for `runs` runs: `jobs` workers (0: one a
    core), never more than the runs, and the cores shared out among them."""
    cores = cores or os.cpu_count() or 1
    n = max(1, min(jobs or cores, runs))
    return n, max(1, cores // n)


def _start(threads):
    # read by runtime.init, before the worker's first run initialises Taichi
    os.environ["TISPH_THREADS"] = str(threads)


def run_all(tasks, jobs, threads, done):
    """tasks: [(key, fn, args)], in the order to start them (the longest first keeps the last
    worker from finishing alone). Calls done(key, result, error) in this process as each ends;
    error is the exception a run raised, else None. One job runs them here, one after another.
    An interrupt (a run that raises SystemExit, Ctrl-C) cancels the runs not started and stops."""
    if jobs <= 1:
        for key, fn, args in tasks:
            try:
                r, e = fn(*args), None
            except Exception as exc:        # noqa: BLE001 - reported to done, the others go on
                r, e = None, exc
            done(key, r, e)
        return
    ctx = multiprocessing.get_context("spawn")   # a fresh interpreter: no Taichi state forked
    ex = cf.ProcessPoolExecutor(jobs, mp_context=ctx, initializer=_start, initargs=(threads,))
    try:
        futures = {ex.submit(fn, *args): key for key, fn, args in tasks}
        for f in cf.as_completed(futures):
            try:
                r, e = f.result(), None
            except Exception as exc:        # noqa: BLE001
                r, e = None, exc
            done(futures[f], r, e)
    finally:
        ex.shutdown(wait=True, cancel_futures=True)
