#!/usr/bin/python3
"""Counts test cases in JUnit XML under a folder: prints each failure and a line
'N passed, N failed, N skipped'. (catkin_test_results counts gtest 1.12's nested
<testsuites> twice, so it is not used for the numbers.)"""
import pathlib
import sys
import xml.etree.ElementTree as ET

root = pathlib.Path(sys.argv[1])
passed = failed = skipped = 0
for path in sorted(root.rglob("*.xml")):
    try:
        tree = ET.parse(path)
    except ET.ParseError as e:
        print(f"FAILED {path}: unreadable result file ({e})")
        failed += 1
        continue
    for case in tree.iter("testcase"):
        name = f"{case.get('classname', '')}.{case.get('name', '')}"
        problems = case.findall("failure") + case.findall("error")
        if problems:
            failed += 1
            print(f"FAILED {name} ({path.name})")
            for p in problems:
                text = (p.get("message") or "") + "\n" + (p.text or "")
                for line in text.strip().splitlines()[:20]:
                    print(f"    {line}")
        elif case.find("skipped") is not None or case.get("status") == "notrun":
            skipped += 1
        else:
            passed += 1
print(f"tests: {passed} passed, {failed} failed, {skipped} skipped")
