#!/usr/bin/env python3
"""Models ctest's schedule on the test durations of a run, to compare settings without rerunning.

Usage: .ci/ctest_schedule.py <run_tests.log of `make test`> [<-j> [<cpu slots>]]
e.g. `.ci/ctest_schedule.py catkin_ws/run_tests.log 2 2` (what `make test` does: ctest -j2 with
cmake/ctest_cpu.json's two cpu slots). TRACE=1 prints each test's start and end.
Reads the COST/lock/slot rules from cmake/workspace.cmake; starts tests in COST order as ctest does,
skipping one that does not fit (lock held, cpu slots taken: a test takes one, a `light` one none, a
`both_cpus` one two), RUN_SERIAL alone. It assumes a test takes as long as it did in the run, whatever
runs beside it. Checked: 414 s for a -j2 run that took 412 s, 455 s for a three-lane run that took
454 s, 345 s for a -j2 run (soak_short RUN_SERIAL) that took 343 s.
"""
import os
import re
import sys

log = sys.argv[1]
jobs = int(sys.argv[2]) if len(sys.argv) > 2 else 2
slots = int(sys.argv[3]) if len(sys.argv) > 3 else 2
trace = os.environ.get("TRACE")
ws = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cmake", "workspace.cmake")
body = open(ws).read().split("set(_WS_TEST_RULES")[1].split("\n)")[0]
rules = [r.strip().split('"')[1].split() for r in body.splitlines() if r.strip().startswith('"')]

tests = []
for line in open(log):
    m = re.search(r"Test +#\d+: (\S+) .*(?:Passed|Failed) +([0-9.]+) sec", line)
    if not m:
        continue
    name, dur, cost, locks, serial, cpus = m.group(1), float(m.group(2)), 0, set(), False, 1
    for r in rules:
        if re.match("^_ctest_" + r[0], name):
            cost = int(r[1])
            words = set(r[2].split(",")) if len(r) > 2 else set()
            serial = "RUN_SERIAL" in words
            cpus = 2 if "both_cpus" in words else 0 if "light" in words else 1
            locks = words - {"RUN_SERIAL", "both_cpus", "light"}
            break
    tests.append((name, dur, cost, locks, serial, cpus))
tests.sort(key=lambda t: -t[2])

now, running, pending = 0.0, [], list(tests)
while pending or running:
    started = True
    while started:
        started = False
        for t in list(pending):
            if any(r[1][4] for r in running) or len(running) >= jobs or (t[4] and running):
                break
            if sum(r[1][5] for r in running) + t[5] > slots or any(t[3] & r[1][3] for r in running):
                continue
            running.append((now + t[1], t))
            pending.remove(t)
            started = True
            if trace:
                print("%6.0f %6.0f %d %s" % (now, now + t[1], t[5], t[0][7:80]))
            if t[4]:
                break
    running.sort(key=lambda r: r[0])
    now = running.pop(0)[0]
print("-j%d, %d cpu slots: %.0f s (sum of the tests' times %.0f s)" % (jobs, slots, now, sum(t[1] for t in tests)))
