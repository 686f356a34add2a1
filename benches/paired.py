#!/usr/bin/env python3
"""Whole-process timing of two or more commands, run alternately.

    python3 benches/paired.py [--runs N] [--warmup K] [--phase NAME] -- 'CMD A' 'CMD B' ...

Each round runs every command once, in turn, so a machine whose speed drifts
affects all of them alike (hyperfine runs each command's runs back to back).
For each command it prints the median wall time, CPU time (user + sys of the
process and its children), peak resident memory, and the ratio of each median
to the first command's. With --phase NAME it also reads a `probelab --profile`
line naming that phase from standard error and reports its median seconds.

Only the Python standard library is used; commands are split with shlex and
run without a shell. A command that exits non-zero stops the measurement.
"""

import argparse
import os
import re
import shlex
import statistics
import subprocess
import sys
import time


def run_once(argv, phase):
    start = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    err = proc.stderr.read().decode("utf-8", "replace")
    proc.stderr.close()
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        sys.exit(f"paired.py: {' '.join(argv)} exited {proc.returncode}:\n{err[-2000:]}")
    cpu = usage.ru_utime + usage.ru_stime
    peak_mib = usage.ru_maxrss / 1024.0
    phase_s = None
    if phase:
        # `probelab --profile` rows read "  reference   0.013   75.4%   1" (thread seconds).
        for line in err.splitlines():
            m = re.match(r"\s*" + re.escape(phase) + r"\s+([0-9.]+)\s", line)
            if m:
                phase_s = float(m.group(1))
                break
    return wall, cpu, peak_mib, phase_s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7, help="rounds measured (default 7)")
    ap.add_argument("--warmup", type=int, default=1, help="rounds run first and discarded")
    ap.add_argument("--phase", help="a --profile phase to report, e.g. reference")
    ap.add_argument("commands", nargs="+")
    args = ap.parse_args()
    argvs = [shlex.split(c) for c in args.commands]
    samples = [[] for _ in argvs]
    for round_ in range(args.warmup + args.runs):
        for i, argv in enumerate(argvs):
            r = run_once(argv, args.phase)
            if round_ >= args.warmup:
                samples[i].append(r)
    med = []
    for i, cmd in enumerate(args.commands):
        s = samples[i]
        wall = statistics.median(x[0] for x in s)
        cpu = statistics.median(x[1] for x in s)
        peak = max(x[2] for x in s)
        phases = [x[3] for x in s if x[3] is not None]
        ph = statistics.median(phases) if phases else None
        med.append((wall, cpu, ph))
        lo = min(x[0] for x in s)
        hi = max(x[0] for x in s)
        line = (f"[{i}] wall {wall:.4f} s (min {lo:.4f}, max {hi:.4f}), cpu {cpu:.4f} s, "
                f"peak {peak:.1f} MiB")
        if ph is not None:
            line += f", {args.phase} {ph * 1e3:.2f} ms"
        print(line)
        print(f"    {cmd}")
    for i in range(1, len(med)):
        ratio = f"[{i}]/[0]: wall {med[i][0] / med[0][0]:.3f}, cpu {med[i][1] / med[0][1]:.3f}"
        if med[i][2] and med[0][2]:
            ratio += f", {args.phase} {med[i][2] / med[0][2]:.3f}"
        print(ratio)
    print(f"{args.runs} alternating rounds after {args.warmup} warm-up; medians; "
          f"load average at end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
