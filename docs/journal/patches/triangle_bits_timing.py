# Timing builds of the tenth part (BENCHMARKS, issue 17): count_pixels enters each run start's
# triangle in a made-up bitset (the vertex cull buffer reused, numbers aliased) instead of
# marking its chunks. Outputs are wrong; only the times count. Usage, from the repository root:
#   python3 docs/journal/patches/triangle_bits_timing.py T1|T2|T3|T4 && cargo build --release -p render
#   git checkout crates/tiling/src/wgsl/mid_classify.wgsl
import sys,re
v=sys.argv[1]
p='crates/tiling/src/wgsl/mid_classify.wgsl'
s=open(p).read()
start=s.index('fn tiling_mark_triangle(px: TilingPixel) -> bool {')
end=s.index('// One pixel\'s part in count_pixels')
if v=='T1':
    mark='atomicOr(&vertex_cull[(t / 32u) % n], 1u << (t % 32u));'
elif v in ('T2','T4'):
    mark='atomicOr(&vertex_cull[t % n], 1u << ((t / n) % 32u));'
elif v=='T3':
    mark='let w = t % n; let bit = 1u << ((t / n) % 32u); if ((atomicLoad(&vertex_cull[w]) & bit) == 0u) { atomicOr(&vertex_cull[w], bit); }'
body='''fn tiling_mark_triangle(px: TilingPixel) -> bool {
    let t = table[px.mb].first_chunk * 64u + px.instance * table[px.mb].primitive_count + px.prim;
    let n = max(arrayLength(&vertex_cull), 1u);
    %s
    return true;
}

''' % mark
s=s[:start]+body+s[end:]
if v=='T4':
    s=s.replace('tiling_run_start(p.x, p.y, word, left_in_quad, left, up_in_quad, up)\n','true\n')
open(p,'w').write(s)
