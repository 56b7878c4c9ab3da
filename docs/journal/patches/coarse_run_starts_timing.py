# Timing builds of the tenth part (BENCHMARKS, issue 17): run starts over `word >> k` (k from
# the command line). Outputs are wrong; only the times count. Usage, from the repository root:
#   python3 docs/journal/patches/coarse_run_starts_timing.py 8 && cargo build --release -p render
#   git checkout crates/tiling/src/wgsl/mid_classify.wgsl
import sys
k=sys.argv[1]
p='crates/tiling/src/wgsl/mid_classify.wgsl'
s=open(p).read()
a='if (l == word && tiling_valid_bit(i - 1u)) {'
b='if (u == word && tiling_valid_bit(i - params.width)) {'
assert a in s and b in s
s=s.replace(a,'if ((l >> %su) == (word >> %su) && tiling_valid_bit(i - 1u)) {'%(k,k))
s=s.replace(b,'if ((u >> %su) == (word >> %su) && tiling_valid_bit(i - params.width)) {'%(k,k))
open(p,'w').write(s)
