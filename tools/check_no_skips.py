#!/usr/bin/env python3
"""Fails when a CTest run skipped or did not run any test.

Usage: check_no_skips.py JUNIT.xml   (from `ctest --output-junit JUNIT.xml`)

CTest writes one <testcase> per registered test, with status="run" or "fail"
for tests that ran and status="notrun" or "disabled" (and a <skipped> element)
for the rest: a GTEST_SKIP (gtest_discover_tests sets SKIP_REGULAR_EXPRESSION
"[  SKIPPED ]"), a SKIP_RETURN_CODE, a DISABLED test, a fixture whose set-up
failed, a missing executable. Any of those, or a file with no test at all,
is an error here: the suite must not skip silently (docs/TESTING.md).
"""
import sys
import xml.etree.ElementTree as ET


def main(argv):
    if len(argv) != 2:
        print("usage: check_no_skips.py JUNIT.xml", file=sys.stderr)
        return 2
    try:
        root = ET.parse(argv[1]).getroot()
    except (OSError, ET.ParseError) as e:
        print(f"check_no_skips: {argv[1]}: {e}", file=sys.stderr)
        return 2
    cases = list(root.iter("testcase"))
    not_run = []
    for case in cases:
        status = case.get("status", "")
        skipped = case.find("skipped")
        if status not in ("run", "fail") or skipped is not None:
            why = skipped.get("message", "") if skipped is not None else ""
            not_run.append(f"{case.get('name')} (status {status or '?'}{': ' + why if why else ''})")
    if not cases:
        print(f"check_no_skips: {argv[1]}: no test cases", file=sys.stderr)
        return 1
    if not_run:
        print(f"check_no_skips: {len(not_run)} of {len(cases)} tests did not run:", file=sys.stderr)
        for line in not_run:
            print(f"  {line}", file=sys.stderr)
        return 1
    print(f"check_no_skips: all {len(cases)} tests ran (none skipped or disabled)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
