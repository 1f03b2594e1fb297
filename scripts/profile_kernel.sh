#!/usr/bin/env bash
# Where the path-tracing kernel spends its time on lavapipe, by machine instruction.
#
# lavapipe JIT-compiles the kernel with LLVM into anonymous executable memory, which perf
# samples but cannot name. This script renders SCENE with METHOD for a while, samples it with
# `perf record`, copies the JIT code out of the process with gdb, disassembles it with objdump,
# and prints the share of samples per block of code (with its count of divisions, a landmark:
# each watertight triangle test has one) and by instruction, with the share spent on stack
# memory (register spills and reloads). Two builds compare by running it on each.
#
# Needs perf (perf_event_paranoid <= 2 for one's own processes), gdb and objdump.
# Usage: scripts/profile_kernel.sh SCENE [METHOD] [BLOCK_BYTES]     (default mis, 4096)
#   PATHLAB=path/to/pathlab to profile another build; OUT=dir for the files (default a temp dir).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:?usage: scripts/profile_kernel.sh SCENE [METHOD] [BLOCK_BYTES]}
method=${2:-mis}
block=${3:-4096}
pathlab=${PATHLAB:-$(pwd)/target/release/pathlab}
for tool in perf gdb objdump; do
    command -v $tool >/dev/null || { echo "profile_kernel.sh needs $tool" >&2; exit 1; }
done
out=${OUT:-$(mktemp -d)}
mkdir -p "$out"
"$pathlab" render "$scene" --method "$method" --spp 1000000 --width 256 --height 256 -q -o "$out/long.exr" >/dev/null 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
# Past pipeline creation and the first dispatch (where lavapipe compiles).
sleep "${WARMUP:-5}"
perf record -o "$out/perf.data" -F 1999 -p $pid -- sleep "${SECONDS_SAMPLED:-5}" >/dev/null 2>&1
perf report -i "$out/perf.data" --no-children --sort sym 2>/dev/null | grep '%' | awk '{print $1, $3}' > "$out/hot.txt"
# The kernel's code: of the anonymous executable mappings (lavapipe's JIT code; not the vdso),
# the one holding the most samples (a large kernel's module has several: Veach's scene).
region=$(grep -E ' r-xp 00000000 00:00 0 +$' /proc/$pid/maps | cut -d' ' -f1 | python3 -c '
import sys
hot = []
for line in open(sys.argv[1]):
    share, addr = line.split()
    try:
        hot.append((int(addr, 16), float(share.rstrip("%"))))
    except ValueError:
        pass
def weight(region):
    lo, hi = (int(x, 16) for x in region.split("-"))
    return sum(v for a, v in hot if lo <= a < hi)
print(max(sys.stdin.read().split(), key=weight))' "$out/hot.txt")
lo=0x${region%-*}
hi=0x${region#*-}
gdb -p $pid -batch -ex "dump memory $out/jit.bin $lo $hi" >/dev/null 2>&1
kill $pid
objdump -D -b binary -mi386:x86-64 --adjust-vma=$lo "$out/jit.bin" > "$out/jit.asm"
echo "kernel code: $lo-$hi ($(( hi - lo )) bytes); files in $out"
python3 - "$out" "$block" <<'PY'
import collections, re, sys
out, block = sys.argv[1], int(sys.argv[2])
asm, order = {}, []
for line in open(f"{out}/jit.asm"):
    m = re.match(r"\s+([0-9a-f]+):\t[^\t]*\t(.*)", line)
    if m:
        a = int(m.group(1), 16)
        asm[a] = m.group(2)
        order.append(a)
hot = collections.Counter()
for line in open(f"{out}/hot.txt"):
    share, addr = line.split()
    try:
        a = int(addr, 16)
    except ValueError:
        continue
    if a in asm:
        hot[a] += float(share.rstrip("%"))
lo = order[0]
# lavapipe compiles the kernel again at dispatches (its uniform inlining), and a large kernel's
# copies then lie side by side in one mapping, byte for byte the same: fold them onto one copy.
code = open(f"{out}/jit.bin", "rb").read()
if hot:
    h = max(hot, key=hot.get) - lo
    window = code[h:h + 256]
    starts = [m.start() for m in re.finditer(re.escape(window), code)] if len(window) == 256 else []
    if len(starts) > 1:
        period = starts[1] - starts[0]
        phase = starts[0] % period
        if all(code[o:o + 4096] == code[o + period:o + period + 4096] for o in starts[:-1]):
            folded = collections.Counter()
            for a, v in hot.items():
                off = a - lo
                if off >= phase:
                    c = lo + phase + (off - phase) % period
                    if c in asm:
                        folded[c] += v
            hot = folded
            order = [a for a in order if phase <= a - lo < phase + period]
            lo = order[0]
            print(f"{len(starts)} copies of the kernel ({period} bytes apart) folded onto one")
total = sum(hot.values()) or 1.0
blocks, count, divs = collections.Counter(), collections.Counter(), collections.Counter()
for a in order:
    count[(a - lo) // block] += 1
    divs[(a - lo) // block] += "div" in asm[a]
for a, v in hot.items():
    blocks[(a - lo) // block] += v
print(f"{'offset':>8} {'samples':>8} {'instructions':>12} {'divisions':>9}")
for k in sorted(count):
    print(f"{k * block:8x} {100 * blocks[k] / total:7.1f}% {count[k]:12d} {divs[k]:9d}")
ops = collections.Counter()
for a, v in hot.items():
    ops[asm[a].split()[0]] += v
print("by instruction:", ", ".join(f"{k} {100 * v / total:.1f}%" for k, v in ops.most_common(12)))
spill = sum(v for a, v in hot.items() if "(%rsp" in asm[a])
print(f"on stack memory (spills and reloads): {100 * spill / total:.1f}%")
PY
