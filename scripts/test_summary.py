#!/usr/bin/env python3
"""Counts test cases in the JUnit XML files under a catkin test_results folder.

catkin_test_results adds the <testsuites> totals to the per-suite ones for newer
gtest output, so it double counts; this counts <testcase> elements instead.
Prints the failing cases, then one line "N passed, N failed, N skipped".
Exits 1 on any failure or error, or when no test ran.
"""
import pathlib
import sys
import xml.etree.ElementTree as ET


def main(results_dir):
    passed, failed, skipped, bad_files = 0, [], 0, []
    for path in sorted(pathlib.Path(results_dir).rglob("*.xml")):
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as err:
            bad_files.append(f"{path}: unreadable result file ({err})")
            continue
        cases = list(root.iter("testcase"))
        if not cases and root.get("errors", "0") != "0":
            bad_files.append(f"{path}: the test did not run (errors={root.get('errors')})")
        for case in cases:
            name = f"{path.relative_to(results_dir)}: {case.get('classname')}.{case.get('name')}"
            if case.find("failure") is not None or case.find("error") is not None:
                failed.append(name)
            elif case.find("skipped") is not None or case.get("status") == "notrun":
                skipped += 1
            else:
                passed += 1
    for line in failed + bad_files:
        print("FAILED", line)
    n_failed = len(failed) + len(bad_files)
    print(f"{passed} passed, {n_failed} failed, {skipped} skipped")
    return 0 if n_failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
