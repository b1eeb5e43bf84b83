#!/usr/bin/env python3
"""Events per call of named functions in a Callgrind profile (scripts/count-instructions.sh).

Usage: count-instructions.py CALLGRIND-OUT LABEL FUNCTION [LABEL FUNCTION ...]

Inclusive events come from `callgrind_annotate --inclusive=yes`. Calls come from the profile's
per-instruction records (Callgrind's --dump-instr=yes): the execution count of a function's
lowest instruction address, its entry, which no loop jumps back to. The call records of the
profile are no help: with --toggle-collect, a call from code that is not collected carries
only part of the callee's cost and count.
"""
import re
import subprocess
import sys

if len(sys.argv) < 4 or len(sys.argv) % 2 != 0:
    sys.exit(__doc__)
path, *targets = sys.argv[1:]
labels = targets[0::2]
names = targets[1::2]
positions = 1  # position columns before the costs (instr, and line unless left out)
events = []  # the profile's event names, in the order of its cost columns
entry = {}  # function -> (lowest instruction address seen, its execution count)
fnames, current, last = {}, None, 0  # compressed names, the current function, last address
pending_call = False  # the next cost line belongs to a call record
with open(path) as f:
    for line in f:
        line = line.rstrip("\n")
        if line.startswith("events:"):
            events = line.split()[1:]
            continue
        if line.startswith("positions:"):
            positions = len(line.split()) - 1
            continue
        m = re.match(r"(c?fn)=\((\d+)\)(?: (.*))?", line)
        if m:
            if m.group(3):
                fnames[m.group(2)] = m.group(3)
            if m.group(1) == "fn":
                current = fnames.get(m.group(2), "")
            continue
        if line.startswith("calls="):
            pending_call = True
            continue
        if not line or line[0] not in "0123456789+-*":
            continue
        parts = line.split()
        a = parts[0]
        if a.startswith("0x"):
            addr = int(a, 16)
        elif a[0] in "+-":
            addr = last + int(a)
        elif a == "*":
            addr = last
        else:
            addr = int(a)
        last = addr
        if pending_call:
            pending_call = False
            continue
        if current in names and len(parts) > positions:
            ir = int(parts[positions])  # Ir, the first event
            best = entry.get(current)
            if best is None or addr < best[0]:
                entry[current] = (addr, ir)
annotate = subprocess.run(
    ["callgrind_annotate", "--inclusive=yes", "--threshold=100", "--show=" + ",".join(events),
     path], capture_output=True, text=True, check=True).stdout
print("%-22s %10s %10s %11s %12s" % ("entry point", "calls", "instr/ray", "branches/ray",
                                     "mispred/ray"))
for label, name in zip(labels, names):
    if name not in entry:
        continue
    calls = entry[name][1]
    for row in annotate.splitlines():
        if row.rstrip().endswith(name) or (name + " [") in row:
            values = [int(v.replace(",", "")) if v not in (".",) else 0
                      for v in re.findall(r"(?:^|\s)([\d,]+|\.)(?=\s)", row)]
            e = dict(zip(events, values))
            per = lambda *keys: sum(e.get(k, 0) for k in keys) / calls
            print("%-22s %10d %10.1f %11.1f %12.2f" % (label, calls, per("Ir"), per("Bc", "Bi"),
                                                       per("Bcm", "Bim")))
            break
