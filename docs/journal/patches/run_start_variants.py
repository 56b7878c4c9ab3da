# Variants of the eleventh part (BENCHMARKS, issue 17), each with the correct output (GPU ==
# CPU twin): R loads the table row's three mark fields before the run-start test; L marks
# the quad's run starts after its four pixels, in a loop over them (the pixels kept); L2 is
# L with each run start decoded again from its word. Usage, from the repository root:
#   python3 docs/journal/patches/run_start_variants.py R|L|L2 && cargo build --release -p render
#   git checkout crates/tiling/src/wgsl/mid_classify.wgsl
import sys
v = sys.argv[1]
assert v in ('R', 'L', 'L2')
p = 'crates/tiling/src/wgsl/mid_classify.wgsl'
s = open(p).read()

def rep(a, b):
    global s
    assert a in s, a
    s = s.replace(a, b, 1)

MARK = '''    if (TILING_VERTEX_CULL_CODE && (params.flags & TILING_FLAG_VERTEX_CULL) != 0u && tiling_run_start(p.x, p.y, word, left_in_quad, left, up_in_quad, up)
        && !tiling_mark_triangle(px)) {
        tiling_stat(TILING_STAT_BAD_INDICES, 1u);
    }'''
START = '    out.start = TILING_VERTEX_CULL_CODE && (params.flags & TILING_FLAG_VERTEX_CULL) != 0u && tiling_run_start(p.x, p.y, word, left_in_quad, left, up_in_quad, up);'

if v == 'R':
    rep('''fn tiling_mark_triangle(px: TilingPixel) -> bool {
    // The row's three fields, not the whole 64-byte row.
    let first_index = table[px.mb].first_index;
    let vertex_count = table[px.mb].vertex_count;
    let first_chunk = table[px.mb].first_chunk;
''', 'fn tiling_mark_triangle(px: TilingPixel, first_index: u32, vertex_count: u32, first_chunk: u32) -> bool {\n')
    rep(MARK, '''    let first_index = table[px.mb].first_index;
    let vertex_count = table[px.mb].vertex_count;
    let first_chunk = table[px.mb].first_chunk;
''' + MARK.replace('tiling_mark_triangle(px)', 'tiling_mark_triangle(px, first_index, vertex_count, first_chunk)'))
else:
    kept = v == 'L'
    rep('''struct TilingCounted {
    key: u32,
    mask: u32,
    record: u32,
}''', '''struct TilingCounted {
    key: u32,
    mask: u32,
    record: u32,
    start: bool,%s
}''' % ('\n    px: TilingPixel,' if kept else ''))
    rep('var out = TilingCounted(TILING_NONE, 0u, TILING_PX_EMPTY);',
        'var out = TilingCounted(TILING_NONE, 0u, TILING_PX_EMPTY, false%s);' % (', TilingPixel(0u, 0u, 0u, 0u, 0u)' if kept else ''))
    rep(MARK, ('    out.px = px;\n' if kept else '') + START)
    if kept:
        pick = '''        var px = p0.px;
        if (k == 1u) { px = p1.px; }
        if (k == 2u) { px = p2.px; }
        if (k == 3u) { px = p3.px; }
'''
    else:
        pick = '''        var word = w.x;
        if (k == 1u) { word = w.y; }
        if (k == 2u) { word = w.z; }
        if (k == 3u) { word = w.w; }
        let p = tiling_quad_pixel(gid, k);
        let px = tiling_decode(word, p.y * params.width + p.x);
'''
    rep('    tiling_stat(TILING_STAT_COMMANDS, u32(p0.key', '''    var todo = u32(p0.start) | (u32(p1.start) << 1u) | (u32(p2.start) << 2u) | (u32(p3.start) << 3u);
    while (todo != 0u) {
        let k = firstTrailingBit(todo);
        todo &= todo - 1u;
''' + pick + '''        if (!tiling_mark_triangle(px)) {
            tiling_stat(TILING_STAT_BAD_INDICES, 1u);
        }
    }
    tiling_stat(TILING_STAT_COMMANDS, u32(p0.key''')
open(p, 'w').write(s)
