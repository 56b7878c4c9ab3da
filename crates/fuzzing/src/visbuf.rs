//! Fuzz bodies for the `visbuf` crate: vis-ID decode of arbitrary words, vertex decode of
//! arbitrary 32 bytes, and both primitive-ID mesh encoders (all four strategies) on
//! arbitrary meshes, each output checked by an independent decoder. Nothing here may panic
//! except a check.

use visbuf::{Error, PrimitiveBits, PrimitiveIdMesh, VisId, VisIdRanges, VisLayout, VisbufVertex};

use crate::Input;

/// Vis-ID decode: any word with any primitive-bit count decodes without panicking; what
/// decodes repacks to the same word; words resolve through ranges built from the input.
pub fn visbuf_id_decode(data: &[u8]) {
    let mut input = Input::new(data);
    let layout = if input.u8() & 1 == 0 {
        VisLayout::Standard
    } else {
        VisLayout::Vrs
    };
    // A few batches from the input (errors allowed, never panics).
    let mut ranges = VisIdRanges::new(layout);
    for _ in 0..input.u8() % 8 {
        let (pc, ic) = (input.u32() % 70_000, input.u32() % 70_000);
        if let Err(e) = ranges.push(pc, ic) {
            assert!(!e.to_string().is_empty());
        }
    }
    while input.remaining() > 0 {
        let word = VisId(input.u32());
        let raw_bits = u32::from(input.u8());
        let Ok(bits) = PrimitiveBits::new(raw_bits) else {
            assert!(raw_bits > visbuf::MAX_PRIMITIVE_BITS);
            continue;
        };
        match word.unpack(layout, bits) {
            Some(f) => assert_eq!(VisId::pack(layout, bits, f), Ok(word)),
            None => assert_eq!(word.micro_batch(layout), layout.reserved_micro_batch()),
        }
        if let Some(hit) = ranges.resolve(word) {
            let r = ranges.ranges()[hit.batch as usize];
            assert!(hit.instance < r.instance_count && hit.primitive < r.primitive_count);
            assert_eq!(
                ranges.pack(hit.batch, hit.instance, hit.primitive, hit.rate),
                Ok(word)
            );
        }
    }
}

/// Vertex decode: any 32 bytes unpack without panicking, within the formats' ranges, and
/// a finite result repacks to a vertex that unpacks the same.
pub fn visbuf_vertex_decode(data: &[u8]) {
    let mut input = Input::new(data);
    let words: [u32; 8] = core::array::from_fn(|_| input.u32());
    let v = VisbufVertex::from_words(words);
    assert_eq!(v.to_words(), words);
    let u = v.unpack();
    assert!(u.core.normal.abs().max_element() <= 1.0);
    assert!(u.core.tangent.abs().max_element() <= 1.0);
    assert!(u.uv.min_element() >= 0.0 && u.uv.max_element() < 8.0);
    assert!(u.color.min_element() >= 0.0 && u.color.max_element() <= 1.0);
    for i in 0..visbuf::vertex::SLOT_COUNT {
        assert!(v.slot_bits(i).is_some());
    }
    match VisbufVertex::pack(&u) {
        Ok(p) => {
            let back = p.unpack();
            assert_eq!(
                back.core.hpos.to_array().map(f32::to_bits),
                u.core.hpos.to_array().map(f32::to_bits)
            );
            assert_eq!(back.core.normal, u.core.normal);
            assert_eq!(back.core.tangent.truncate(), u.core.tangent.truncate());
            assert_eq!(
                back.core.tangent.w,
                if u.core.tangent.w < 0.0 { -1.0 } else { 1.0 }
            );
            assert_eq!((back.uv, back.color, back.extra), (u.uv, u.color, u.extra));
            assert_eq!(back.core.prev_hpos, u.core.prev_hpos);
        }
        Err(Error::NonFinite { .. }) => {}
        Err(e) => panic!("a decoded vertex must repack unless non-finite: {e}"),
    }
}

/// Builds a mesh from fuzz input: a vertex count, then 16-bit indices, folded into range
/// unless the first byte asks for raw ones (to reach the error paths).
fn mesh(input: &mut Input<'_>) -> (Vec<u32>, u32, bool) {
    let raw = input.u8() & 0x80 != 0;
    let vertex_count = u32::from(input.u16()) % 300 + u32::from(raw) * 65_300;
    let mut indices = Vec::new();
    while input.remaining() >= 2 && indices.len() < 3 * 4096 {
        let i = u32::from(input.u16());
        indices.push(if raw || vertex_count == 0 {
            i
        } else {
            i % vertex_count
        });
    }
    if !raw {
        indices.truncate(indices.len() / 3 * 3);
    }
    (indices, vertex_count, raw)
}

fn check_common(src: &[u32], vertex_count: u32, m: &PrimitiveIdMesh) {
    assert_eq!(m.indices.len(), src.len());
    assert_eq!(m.source_vertex_count, vertex_count);
    assert_eq!(m.remap.len(), m.payloads.len());
    assert!((0..vertex_count as usize).all(|v| m.remap[v] == v as u32));
    assert!(m.remap.iter().all(|&r| r < vertex_count));
    assert!(m.payloads.iter().all(|&p| p < 65_536));
    assert!(m.indices.iter().all(|&i| (i as usize) < m.remap.len()));
}

fn encode_errors_are_right(src: &[u32], vertex_count: u32, e: Error) {
    match e {
        Error::IndexCountNotMultipleOf3 { len } => assert!(len % 3 != 0),
        Error::IndexOutOfRange { index, .. } => assert!(index >= vertex_count),
        Error::TooManyVertices { count, .. } => assert!(count > visbuf::MAX_VERTICES_PER_GEOMETRY),
        Error::TooManyPrimitives { .. } => assert!(src.len() / 3 > 65_536),
        e => panic!("unexpected encoder error {e}"),
    }
}

/// The provoking-vertex encoders: every triangle's first vertex carries its index and the
/// corners are a rotation of the source triangle.
pub fn visbuf_encode_provoking(data: &[u8]) {
    let mut input = Input::new(data);
    let (src, vc, _) = mesh(&mut input);
    for encode in [
        visbuf::encode_provoking::<u32>,
        visbuf::encode_provoking_greedy::<u32>,
    ] {
        match encode(&src, vc) {
            Ok(m) => {
                check_common(&src, vc, &m);
                for (t, (s, o)) in src.chunks(3).zip(m.indices.chunks(3)).enumerate() {
                    assert_eq!(m.payloads[o[0] as usize], t as u32);
                    let c = [o[0], o[1], o[2]].map(|i| m.remap[i as usize]);
                    assert!(
                        c == [s[0], s[1], s[2]]
                            || c == [s[1], s[2], s[0]]
                            || c == [s[2], s[0], s[1]]
                    );
                }
            }
            Err(e) => encode_errors_are_right(&src, vc, e),
        }
    }
}

/// The XOR encoders: every triangle's three payloads XOR to its index and its corners copy
/// the source corners in order.
pub fn visbuf_encode_xor(data: &[u8]) {
    let mut input = Input::new(data);
    let (src, vc, _) = mesh(&mut input);
    for encode in [visbuf::encode_xor::<u32>, visbuf::encode_xor_greedy::<u32>] {
        match encode(&src, vc) {
            Ok(m) => {
                check_common(&src, vc, &m);
                for (t, (s, o)) in src.chunks(3).zip(m.indices.chunks(3)).enumerate() {
                    let x = o.iter().fold(0, |a, &i| a ^ m.payloads[i as usize]);
                    assert_eq!(x, t as u32);
                    assert_eq!(
                        [o[0], o[1], o[2]].map(|i| m.remap[i as usize]),
                        [s[0], s[1], s[2]]
                    );
                }
            }
            Err(e) => encode_errors_are_right(&src, vc, e),
        }
    }
}
