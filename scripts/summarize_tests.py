#!/usr/bin/python3
"""Counts test cases in JUnit XML files (gtest, rostest) under a folder.

Prints failing cases by name with the first lines of their failure message
(CI shows only the tail of the output: the reason must be next to the name)
and a closing line "N passed, N failed" (with ", N skipped" when any). Exits 1 when a case failed or none ran.
catkin_test_results is not used: Debian's version counts a gtest file's
<testsuites> total on top of its suites, doubling the count.

A rostest writes two kinds of file: rosunit-<test>.xml with the cases the
test node ran, and rostest-<launch>.xml with one wrapper case per <test>. The
cases are counted; a wrapper counts only when it failed (a test node that
crashed or ran out of time leaves no cases of its own).
"""
import pathlib
import sys
import xml.etree.ElementTree as ET

MESSAGE_LINES = 6  # of each failure's message printed under its name


def failure_lines(element, count=MESSAGE_LINES):
    """The first lines of a <failure>/<error>: its message, then its text."""
    text = "\n".join(t for t in (element.get("message", ""), element.text or "") if t.strip())
    lines = [line.rstrip() for line in text.splitlines() if line.strip()]
    return lines[:count]


def main(folder):
    passed = failed = skipped = 0
    broken_files = []
    for path in sorted(pathlib.Path(folder).rglob("*.xml")):
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError:
            broken_files.append(path)
            continue
        wrappers = path.name.startswith("rostest-")
        for case in root.iter("testcase"):
            name = f"{case.get('classname', '')}.{case.get('name', '')}"
            problem = case.find("failure")
            if problem is None:
                problem = case.find("error")
            if problem is not None:
                failed += 1
                print(f"FAILED: {name} ({path.name})")
                for line in failure_lines(problem):
                    print(f"    {line}")
            elif wrappers:
                continue
            elif case.find("skipped") is not None or case.get("result") == "skipped" \
                    or case.get("status") == "notrun":
                skipped += 1
                print(f"SKIPPED: {name} ({path.name})")
            else:
                passed += 1
    for path in broken_files:
        failed += 1
        print(f"FAILED: unreadable result file {path}")
    line = f"{passed} passed, {failed} failed"
    if skipped:
        line += f", {skipped} skipped"
    print(line)
    return 0 if failed == 0 and passed > 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
