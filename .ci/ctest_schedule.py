#!/usr/bin/env python3
"""Models ctest's schedule on the test durations of a run, to compare lane settings without rerunning.

Usage: .ci/ctest_schedule.py <run_tests.log of `make test`> <-j> <lanes> <lanes of a realtime test>
e.g. `.ci/ctest_schedule.py catkin_ws/run_tests.log 3 3 2` (what `make test` does) against `2 2 1` (-j2).
Reads the COST/lock rules from cmake/workspace.cmake; starts tests in COST order as ctest does, skipping
one that does not fit (lock held, lanes taken), RUN_SERIAL alone. It assumes a test takes as long as it
did in the run, whatever runs beside it. Checked: 414 s for a -j2 run that took 412 s, 455 s for a
three-lane run that took 454 s.
"""
import os
import re
import sys

log, jobs, lanes, rt_lanes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
trace = os.environ.get("TRACE")
ws = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cmake", "workspace.cmake")
body = open(ws).read().split("set(_WS_TEST_RULES")[1].split("\n)")[0]
rules = [[x.strip('"') for x in r.split()] for r in body.splitlines() if r.strip().startswith('"')]

tests = []
for line in open(log):
    m = re.search(r"Test +#\d+: (\S+) .*(?:Passed|Failed) +([0-9.]+) sec", line)
    if not m:
        continue
    name, dur, cost, locks, serial = m.group(1), float(m.group(2)), 0, set(), False
    for r in rules:
        if re.match("^_ctest_" + r[0], name):
            cost, lk = int(r[1]), (r[2] if len(r) > 2 else "")
            serial = lk == "RUN_SERIAL"
            locks = set(lk.split(",")) if lk and not serial else set()
            break
    tests.append((name, dur, cost, locks, serial))
tests.sort(key=lambda t: -t[2])


def need(t):
    return rt_lanes if "realtime" in t[3] else 1


now, running, pending = 0.0, [], list(tests)
while pending or running:
    started = True
    while started:
        started = False
        for t in list(pending):
            if any(r[1][4] for r in running) or len(running) >= jobs or (t[4] and running):
                break
            if sum(need(r[1]) for r in running) + need(t) > lanes or any(t[3] & r[1][3] for r in running):
                continue
            running.append((now + t[1], t))
            pending.remove(t)
            started = True
            if trace:
                print("%6.0f %6.0f %d %s" % (now, now + t[1], need(t), t[0][7:80]))
            if t[4]:
                break
    running.sort(key=lambda r: r[0])
    now = running.pop(0)[0]
print("-j%d, %d lanes, realtime takes %d: %.0f s (sum of the tests' times %.0f s)" %
      (jobs, lanes, rt_lanes, now, sum(t[1] for t in tests)))
