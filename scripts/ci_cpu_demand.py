#!/usr/bin/env python3
"""CPU demand of a running test: samples every 0.2 s how many threads of a process tree are
running or runnable (state R), until its root exits, and prints the mean (capped at the core
count) and the share of samples with none. A mean near the core count means the test alone can
fill the machine: at ctest -jN on N cores such tests are CPU-bound, and only less work helps.

Usage: scripts/ci_cpu_demand.py ROOT_PID [--cores 2]
  e.g. ctest --test-dir build-ci -R '^integration.odom_lost$' & sleep 1
       scripts/ci_cpu_demand.py "$(pgrep -n -f multirobot_test.sh)"
"""
import argparse
import os
import time


def tree(root):
    """Pids of root and all its descendants."""
    kids = {}
    for p in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{p}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        ppid = int(stat[stat.rindex(")") + 2:].split()[1])
        kids.setdefault(ppid, []).append(int(p))
    pids, todo = [], [root]
    while todo:
        pid = todo.pop()
        pids.append(pid)
        todo += kids.get(pid, [])
    return pids


def runnable(pids):
    """Threads of pids in state R."""
    n = 0
    for pid in pids:
        try:
            for tid in os.listdir(f"/proc/{pid}/task"):
                with open(f"/proc/{pid}/task/{tid}/stat") as f:
                    stat = f.read()
                n += stat[stat.rindex(")") + 2] == "R"
        except OSError:
            pass  # the process or thread ended meanwhile
    return n


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("root", type=int)
    parser.add_argument("--cores", type=int, default=2)
    args = parser.parse_args()
    samples = []
    while os.path.exists(f"/proc/{args.root}"):
        samples.append(runnable(tree(args.root)))
        time.sleep(0.2)
    if not samples:
        raise SystemExit("ci_cpu_demand: no samples (the process had ended)")
    mean = sum(min(n, args.cores) for n in samples) / len(samples)
    idle = sum(n == 0 for n in samples) / len(samples)
    print(f"{len(samples)} samples: {mean:.2f} runnable threads on average "
          f"(capped at {args.cores}), none runnable in {100 * idle:.0f} %")


if __name__ == "__main__":
    main()
