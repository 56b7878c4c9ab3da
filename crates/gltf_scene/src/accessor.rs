//! Accessors read with every offset, stride and count checked against the bytes there
//! are (gltf's own reader trusts them), sparse substitution applied.

use gltf::accessor::{DataType, Dimensions};

use crate::Error;

/// The most bytes an accessor without a buffer view (all zeros, possibly with sparse
/// values) may expand to: 64 MiB. Such an accessor costs nothing in the file, so its count
/// is not bounded by the file's size.
pub const MAX_VIEWLESS_ACCESSOR_BYTES: usize = 64 << 20;

/// What accessor reading needs: the file's name for errors and the loaded buffers (each
/// cut to its `byteLength`).
pub(crate) struct Data<'a> {
    pub file: &'a str,
    pub buffers: &'a [Vec<u8>],
}

impl Data<'_> {
    fn error(&self, a: &gltf::Accessor<'_>, problem: String) -> Error {
        Error::Accessor {
            file: self.file.to_owned(),
            accessor: a.index(),
            name: a.name().map(str::to_owned),
            problem,
        }
    }

    /// The bytes `[offset, offset + len)` of buffer view `view`, checked.
    fn view_bytes(
        &self,
        a: &gltf::Accessor<'_>,
        view: &gltf::buffer::View<'_>,
    ) -> Result<&[u8], Error> {
        let buffer = &self.buffers[view.buffer().index()];
        let end = view.offset().checked_add(view.length());
        match end {
            Some(end) if end <= buffer.len() => Ok(&buffer[view.offset()..end]),
            _ => Err(self.error(
                a,
                format!(
                    "buffer view {} ({} bytes at offset {}) reaches past the end of buffer {} \
                     ({} bytes)",
                    view.index(),
                    view.length(),
                    view.offset(),
                    view.buffer().index(),
                    buffer.len()
                ),
            )),
        }
    }

    /// The accessor's elements tightly packed (`count × element size` bytes, sparse values
    /// substituted), its component type and component count.
    fn packed(&self, a: &gltf::Accessor<'_>) -> Result<(Vec<u8>, DataType, usize), Error> {
        let dt = a.data_type();
        let comps = a.dimensions().multiplicity();
        let cs = dt.size();
        let es = cs * comps;
        let count = a.count();
        let total = count
            .checked_mul(es)
            .ok_or_else(|| self.error(a, format!("count {count} overflows")))?;
        let mut out;
        if let Some(view) = a.view() {
            let bytes = self.view_bytes(a, &view)?;
            let stride = view.stride().unwrap_or(es);
            if stride < es {
                return Err(self.error(
                    a,
                    format!(
                        "buffer view {} has byteStride {stride}, less than the {es}-byte element",
                        view.index()
                    ),
                ));
            }
            if count > 0 {
                let end = (count - 1)
                    .checked_mul(stride)
                    .and_then(|x| x.checked_add(a.offset()))
                    .and_then(|x| x.checked_add(es));
                if end.is_none_or(|end| end > bytes.len()) {
                    return Err(self.error(
                        a,
                        format!(
                            "{count} elements of {es} bytes (stride {stride}) at byteOffset {} \
                             reach past the end of buffer view {} ({} bytes)",
                            a.offset(),
                            view.index(),
                            bytes.len()
                        ),
                    ));
                }
            }
            out = Vec::with_capacity(total);
            for i in 0..count {
                let at = a.offset() + i * stride;
                out.extend_from_slice(&bytes[at..at + es]);
            }
        } else {
            if total > MAX_VIEWLESS_ACCESSOR_BYTES {
                return Err(self.error(
                    a,
                    format!(
                        "{count} elements without a buffer view ({total} bytes of zeros) pass the \
                         importer's limit of {MAX_VIEWLESS_ACCESSOR_BYTES} bytes"
                    ),
                ));
            }
            out = vec![0; total];
        }
        if let Some(sparse) = a.sparse() {
            let n = sparse.count();
            let indices = sparse.indices();
            let is = match indices.index_type() {
                gltf::accessor::sparse::IndexType::U8 => 1,
                gltf::accessor::sparse::IndexType::U16 => 2,
                gltf::accessor::sparse::IndexType::U32 => 4,
            };
            let iview = indices.view();
            let ib = self.view_bytes(a, &iview)?;
            let vview = sparse.values().view();
            let vb = self.view_bytes(a, &vview)?;
            let need_i = n
                .checked_mul(is)
                .and_then(|x| x.checked_add(indices.offset()));
            let need_v = n
                .checked_mul(es)
                .and_then(|x| x.checked_add(sparse.values().offset()));
            if need_i.is_none_or(|x| x > ib.len()) || need_v.is_none_or(|x| x > vb.len()) {
                return Err(self.error(
                    a,
                    format!("its {n} sparse indices or values reach past their buffer views"),
                ));
            }
            for k in 0..n {
                let at = indices.offset() + k * is;
                let idx = match is {
                    1 => usize::from(ib[at]),
                    2 => usize::from(u16::from_le_bytes([ib[at], ib[at + 1]])),
                    _ => u32::from_le_bytes([ib[at], ib[at + 1], ib[at + 2], ib[at + 3]]) as usize,
                };
                if idx >= count {
                    return Err(self.error(
                        a,
                        format!("sparse index {idx} (entry {k}) is past its count {count}"),
                    ));
                }
                let src = sparse.values().offset() + k * es;
                out[idx * es..(idx + 1) * es].copy_from_slice(&vb[src..src + es]);
            }
        }
        Ok((out, dt, comps))
    }

    /// The accessor as floats, `N` components per element: normalized integers mapped to
    /// [0, 1] or [-1, 1] as glTF defines, other integers converted as they are
    /// (KHR_mesh_quantization). `what` names the use in errors (`"POSITION"`). Errors on
    /// another element type than `N` components and on non-finite floats.
    pub(crate) fn floats<const N: usize>(
        &self,
        a: &gltf::Accessor<'_>,
        what: &str,
    ) -> Result<Vec<[f32; N]>, Error> {
        let dims = a.dimensions();
        let want = match N {
            1 => Dimensions::Scalar,
            2 => Dimensions::Vec2,
            3 => Dimensions::Vec3,
            _ => Dimensions::Vec4,
        };
        if dims != want {
            return Err(self.error(
                a,
                format!("{what} needs type {want:?}, the accessor is {dims:?}"),
            ));
        }
        let (bytes, dt, _) = self.packed(a)?;
        let norm = a.normalized();
        let cs = dt.size();
        let comp = |c: &[u8]| -> f32 {
            match dt {
                DataType::F32 => f32::from_le_bytes([c[0], c[1], c[2], c[3]]),
                DataType::U8 if norm => f32::from(c[0]) / 255.0,
                DataType::U8 => f32::from(c[0]),
                DataType::I8 if norm => (f32::from(c[0] as i8) / 127.0).max(-1.0),
                DataType::I8 => f32::from(c[0] as i8),
                DataType::U16 if norm => f32::from(u16::from_le_bytes([c[0], c[1]])) / 65535.0,
                DataType::U16 => f32::from(u16::from_le_bytes([c[0], c[1]])),
                DataType::I16 if norm => {
                    (f32::from(i16::from_le_bytes([c[0], c[1]])) / 32767.0).max(-1.0)
                }
                DataType::I16 => f32::from(i16::from_le_bytes([c[0], c[1]])),
                DataType::U32 => u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f32,
            }
        };
        let mut out = Vec::with_capacity(bytes.len() / (cs * N).max(1));
        for (i, e) in bytes.chunks_exact(cs * N).enumerate() {
            let mut v = [0.0; N];
            for (k, x) in v.iter_mut().enumerate() {
                *x = comp(&e[k * cs..(k + 1) * cs]);
            }
            if !v.iter().all(|x| x.is_finite()) {
                return Err(self.error(a, format!("{what} element {i} is not finite: {v:?}")));
            }
            out.push(v);
        }
        Ok(out)
    }

    /// An index accessor: scalar unsigned 8, 16 or 32-bit integers.
    pub(crate) fn indices(&self, a: &gltf::Accessor<'_>) -> Result<Vec<u32>, Error> {
        if a.dimensions() != Dimensions::Scalar {
            return Err(self.error(
                a,
                format!(
                    "indices must be SCALAR, the accessor is {:?}",
                    a.dimensions()
                ),
            ));
        }
        let (bytes, dt, _) = self.packed(a)?;
        Ok(match dt {
            DataType::U8 => bytes.iter().map(|&b| u32::from(b)).collect(),
            DataType::U16 => bytes
                .chunks_exact(2)
                .map(|c| u32::from(u16::from_le_bytes([c[0], c[1]])))
                .collect(),
            DataType::U32 => bytes
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
            other => {
                return Err(self.error(
                    a,
                    format!("indices must be unsigned bytes, shorts or ints, not {other:?}"),
                ));
            }
        })
    }
}
