"""Shares of a perf recording's samples by the lavapipe JIT function they fell in.

Usage: attribute.py OUT_DIR (holding jit.txt and perf.data, from lavapipe-profile.sh).
A sample in JIT code counts for the function compiled at the nearest address below it;
one elsewhere for its shared object. Functions are named by their compile order
(lavapipe compiles a compute pass at its first dispatch, so in the first frame's order)
and kind (cs_variant: a compute pass; draw_llvm_gs_variant: the geometry stage; ...).
"""
import collections
import os
import subprocess
import sys

out_dir = sys.argv[1]
functions = []
with open(os.path.join(out_dir, "jit.txt")) as log:
    for index, line in enumerate(log):
        name, address = line.split()
        functions.append((int(address, 16), f"{index}: {name}"))
functions.sort()
script = subprocess.run(
    ["perf", "script", "-i", os.path.join(out_dir, "perf.data"), "-F", "ip,dso"],
    capture_output=True, text=True, check=True,
).stdout
counts = collections.Counter()
for line in script.splitlines():
    fields = line.split(maxsplit=1)
    if len(fields) < 2:
        continue
    ip = int(fields[0], 16)
    dso = os.path.basename(fields[1].strip("()"))
    if dso.startswith("perf-") or "JIT" in dso or "unknown" in dso:
        owner = "JIT, before every compiled function"
        for address, name in functions:
            if address <= ip:
                owner = name
        counts[owner] += 1
    else:
        counts[dso] += 1
total = sum(counts.values())
print(f"{total} samples")
for owner, n in counts.most_common(25):
    print(f"{100 * n / total:6.2f} %  {owner}")
