#!/usr/bin/env python3
"""Replays a ctest run's test times through ctest -jN's order (costliest COST first, then the
order of definition; each test starts when a slot frees) and prints the resulting wall time and
its bound (sum / N). Shows whether the COST properties pack the slots well on a fresh checkout,
which has no timing history.

Usage: scripts/ci_schedule_replay.py BUILD_DIR [--times CTestCostData.txt] [-j 2]
  BUILD_DIR: a configured build (its tests and COST properties, ctest --show-only=json-v1);
  --times: the seconds per test of a finished run (default BUILD_DIR/Testing/Temporary/
  CTestCostData.txt). Tests without a time count 0.1 s. Fixtures and RESOURCE_LOCKs are ignored.
"""
import argparse
import heapq
import json
import subprocess


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build")
    parser.add_argument("--times")
    parser.add_argument("-j", type=int, default=2)
    args = parser.parse_args()
    listing = subprocess.run(["ctest", "--test-dir", args.build, "--show-only=json-v1"],
                             check=True, capture_output=True, text=True).stdout
    tests = json.loads(listing)["tests"]
    cost = {t["name"]: float(p["value"]) for t in tests for p in t.get("properties", [])
            if p["name"] == "COST"}
    seconds = {}
    with open(args.times or f"{args.build}/Testing/Temporary/CTestCostData.txt") as f:
        for line in f:
            fields = line.split()
            if len(fields) == 3:
                seconds[fields[0]] = float(fields[2])
    names = [t["name"] for t in tests]
    order = sorted(range(len(names)), key=lambda i: (-cost.get(names[i], 0.0), i))
    slots = [0.0] * args.j
    for i in order:
        heapq.heappush(slots, heapq.heappop(slots) + seconds.get(names[i], 0.1))
    total = sum(seconds.get(n, 0.1) for n in names)
    print(f"{len(names)} tests, {total:.0f} s in all: {max(slots):.0f} s at -j{args.j} "
          f"(bound {total / args.j:.0f} s)")


if __name__ == "__main__":
    main()
