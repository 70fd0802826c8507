"""Ctrl-C during Simulation.advance_to raises KeyboardInterrupt promptly and leaves the
simulation usable; the progress callback is called while it runs and once at the end. The
child process signals when advance_to is running (its progress callback prints a line):
the test waits on that line, not on a fixed sleep."""

import os
import signal
import subprocess
import sys
import time

import pytest

import spheresweep as ss

CHILD = r"""
import signal
# Ctrl-C's own handler, whatever the parent left: a child started from a background job
# inherits SIGINT ignored, and Python then installs no handler (the test hung for that).
signal.signal(signal.SIGINT, signal.default_int_handler)
import spheresweep as ss
sim = ss.Simulation.periodic_gas(20000, 0.3)
sim.advance_to(0.01)
try:
    # No progress callback (a Python callback would run the signal handler itself): only
    # advance_to's own signal check can stop this. The parent signals once the line is out;
    # a signal landing before the call starts raises on entry, which the test also accepts.
    print("running", flush=True)
    sim.advance_to(1e6)
    print("finished", flush=True)
except KeyboardInterrupt:
    t = sim.time
    print("interrupted", t, flush=True)
    # Usable: it goes on from where it stopped, far enough to collide even if the signal landed
    # on entry, before the lattice's first collisions (about t = 0.05).
    sim.advance_to(t + 1.0)
    print("usable", sim.time, sim.stats["collisions"] > 0, flush=True)
"""


def test_sigint_during_advance_to_raises_keyboard_interrupt_within_a_second():
    child = subprocess.Popen([sys.executable, "-c", CHILD], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline() == "running\n"  # advance_to has started
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        line = child.stdout.readline()
        waited = time.monotonic() - sent
        assert line.startswith("interrupted "), line + child.stderr.read()
        t = float(line.split()[1])
        assert 0 < t < 1e6
        assert waited < 1.0, waited  # the bound; a check runs every 4096 events
        usable = child.stdout.readline().split()
        assert usable[0] == "usable" and float(usable[1]) == pytest.approx(t + 1.0)
        assert usable[2] == "True"
        assert child.wait(60) == 0
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()


def test_progress_is_called_in_order_and_at_the_end():
    sim = ss.Simulation.periodic_gas(4000, 0.25, seed=3)
    calls = []
    started = time.monotonic()
    sim.advance_to(30.0, progress=calls.append)
    elapsed = time.monotonic() - started
    assert calls[-1] == 30.0 and calls == sorted(calls)
    # At most ten a second while running, and the last one.
    assert len(calls) <= elapsed / 0.1 + 2, (len(calls), elapsed)


def test_an_exception_in_progress_stops_the_run_between_two_events():
    sim = ss.Simulation.periodic_gas(4000, 0.25, seed=3)

    def stop(now):
        raise RuntimeError(f"stop at {now}")

    with pytest.raises(RuntimeError, match="stop at"):
        sim.advance_to(1e6, progress=stop)
    t = sim.time
    assert 0 < t < 1e6
    again = ss.Simulation.periodic_gas(4000, 0.25, seed=3)
    again.advance_to(t)  # the stopped run is the same run, up to where it stopped
    assert again.stats == sim.stats
