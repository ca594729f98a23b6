//! Accessors: component sizes, little-endian strided reads and sparse substitution, every
//! offset and count checked against its buffer view.

use super::Loader;
use gltf::json;
use gltf::json::validation::Checked;

/// Largest element count of one accessor we accept.
pub(super) const MAX_ACCESSOR_COUNT: u64 = 1 << 28;

/// The most memory one decoded accessor may take (2 GiB: 178 M vec3 positions).
const MAX_ACCESSOR_BYTES: usize = 2 << 30;

/// A vector for `n` decoded values of 4 bytes, checked against the budget and allocated with
/// `try_reserve` (an error, never an abort, when memory runs out).
fn decoded_vec<T>(ai: usize, n: usize) -> Result<Vec<T>, String> {
    let bytes = n.saturating_mul(4);
    if bytes > MAX_ACCESSOR_BYTES {
        return Err(format!(
            "accessor {ai} would decode to {bytes} bytes, more than the {MAX_ACCESSOR_BYTES} allowed"
        ));
    }
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| format!("accessor {ai}: out of memory for {bytes} bytes"))?;
    Ok(v)
}

fn comp_size(c: json::accessor::ComponentType) -> usize {
    use json::accessor::ComponentType as C;
    match c {
        C::I8 | C::U8 => 1,
        C::I16 | C::U16 => 2,
        C::U32 | C::F32 => 4,
    }
}

fn type_comps(t: json::accessor::Type) -> usize {
    use json::accessor::Type as T;
    match t {
        T::Scalar => 1,
        T::Vec2 => 2,
        T::Vec3 => 3,
        T::Vec4 | T::Mat2 => 4,
        T::Mat3 => 9,
        T::Mat4 => 16,
    }
}

fn read_le<const N: usize>(b: &[u8], at: usize) -> Option<[u8; N]> {
    b.get(at..at.checked_add(N)?)?.try_into().ok()
}

/// One component at byte `at`, as f32 (normalised integers mapped per glTF §3.11).
fn read_comp(
    b: &[u8],
    at: usize,
    c: json::accessor::ComponentType,
    normalized: bool,
) -> Option<f32> {
    use json::accessor::ComponentType as C;
    Some(match c {
        C::F32 => f32::from_le_bytes(read_le(b, at)?),
        C::U8 => {
            let v = read_le::<1>(b, at)?[0] as f32;
            if normalized { v / 255.0 } else { v }
        }
        C::I8 => {
            let v = i8::from_le_bytes(read_le(b, at)?) as f32;
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        C::U16 => {
            let v = u16::from_le_bytes(read_le(b, at)?) as f32;
            if normalized { v / 65535.0 } else { v }
        }
        C::I16 => {
            let v = i16::from_le_bytes(read_le(b, at)?) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        C::U32 => u32::from_le_bytes(read_le(b, at)?) as f32,
    })
}

fn read_uint(b: &[u8], at: usize, c: json::accessor::ComponentType) -> Option<u32> {
    use json::accessor::ComponentType as C;
    Some(match c {
        C::U8 => read_le::<1>(b, at)?[0] as u32,
        C::U16 => u16::from_le_bytes(read_le(b, at)?) as u32,
        C::U32 => u32::from_le_bytes(read_le(b, at)?),
        _ => return None,
    })
}

/// A located, bounds-checked strided array inside a buffer.
struct Strided<'a> {
    data: &'a [u8],
    start: usize,
    stride: usize,
}

impl Strided<'_> {
    fn at(&self, i: usize) -> usize {
        self.start + i * self.stride
    }

    /// Check that `count` elements of `elem` bytes lie inside the data (an error naming
    /// accessor `ai` otherwise).
    fn check_bounds(&self, ai: usize, count: usize, elem: usize) -> Result<(), String> {
        let (start, stride) = (self.start, self.stride);
        if count > 0 {
            let end = (count - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(start))
                .and_then(|x| x.checked_add(elem));
            match end {
                Some(e) if e <= self.data.len() => {}
                _ => {
                    return Err(format!(
                        "accessor {ai} (count {count}, offset {start}, stride {stride}) reads past the end of its {}-byte buffer view (accessor out of bounds)",
                        self.data.len()
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Decoded accessor data: `count × comps` floats or unsigned integers.
pub(super) enum AccessorData {
    Float(Vec<f32>),
    Uint(Vec<u32>),
}

/// What decoding accessor `ai` takes: where its elements lie (None: no buffer view, all
/// zeros), how many, their components and component type.
struct Elements<'a> {
    ai: usize,
    strided: Option<Strided<'a>>,
    count: usize,
    comps: usize,
    ct: json::accessor::ComponentType,
    normalized: bool,
}

impl Elements<'_> {
    /// The `count × comps` components as unsigned integers (U8, U16 or U32 only: indices).
    fn uints(&self) -> Result<Vec<u32>, String> {
        let ai = self.ai;
        if !matches!(
            self.ct,
            json::accessor::ComponentType::U8
                | json::accessor::ComponentType::U16
                | json::accessor::ComponentType::U32
        ) {
            return Err(format!("accessor {ai}: indices must be unsigned integers"));
        }
        self.components(|b, at| read_uint(b, at, self.ct))
    }

    /// The `count × comps` components as floats (normalised integers mapped to [0, 1] or
    /// [−1, 1]).
    fn floats(&self) -> Result<Vec<f32>, String> {
        self.components(|b, at| read_comp(b, at, self.ct, self.normalized))
    }

    /// Every component read by `read(buffer, byte offset)`, in element order; an accessor
    /// without a buffer view is all zeros (glTF 2.0: before sparse substitution, if any).
    fn components<T: Copy + Default>(
        &self,
        read: impl Fn(&[u8], usize) -> Option<T>,
    ) -> Result<Vec<T>, String> {
        let ai = self.ai;
        let mut v: Vec<T> = decoded_vec(ai, self.count * self.comps)?;
        match &self.strided {
            Some(s) => {
                let cs = comp_size(self.ct);
                let bad = || format!("accessor {ai} reads out of bounds");
                for i in 0..self.count {
                    for k in 0..self.comps {
                        v.push(read(s.data, s.at(i) + k * cs).ok_or_else(bad)?);
                    }
                }
            }
            None => v.resize(self.count * self.comps, T::default()),
        }
        Ok(v)
    }
}

impl Loader<'_> {
    /// Locate accessor `ai`'s elements, checking every offset against the buffer.
    fn locate(&self, ai: usize) -> Result<(&json::Accessor, Option<Strided<'_>>, usize), String> {
        let (acc, count, elem) = self.accessor_shape(ai)?;
        let Some(vi) = acc.buffer_view else {
            return Ok((acc, None, elem));
        };
        let strided = self.strided_view(ai, vi.value(), acc, elem)?;
        strided.check_bounds(ai, count, elem)?;
        Ok((acc, Some(strided), elem))
    }

    /// Accessor `ai` with its element count and element size in bytes, once its type and
    /// component type are valid and its count is not too large.
    fn accessor_shape(&self, ai: usize) -> Result<(&json::Accessor, usize, usize), String> {
        let acc = self
            .root
            .accessors
            .get(ai)
            .ok_or_else(|| format!("accessor {ai} does not exist (index out of range)"))?;
        let Checked::Valid(ty) = acc.type_ else {
            return Err(format!("accessor {ai} has an invalid type"));
        };
        let Checked::Valid(ct) = acc.component_type else {
            return Err(format!("accessor {ai} has an invalid component type"));
        };
        let count = acc.count.0;
        if count > MAX_ACCESSOR_COUNT {
            return Err(format!("accessor {ai} count {count} is too large"));
        }
        let elem = type_comps(ty) * comp_size(ct.0);
        Ok((acc, count as usize, elem))
    }

    /// The bytes of buffer view `vi` that accessor `ai` (element size `elem`) reads, with the
    /// accessor's start offset and the view's stride (at least `elem`; `elem` if unset).
    fn strided_view(
        &self,
        ai: usize,
        vi: usize,
        acc: &json::Accessor,
        elem: usize,
    ) -> Result<Strided<'_>, String> {
        let view = self
            .root
            .buffer_views
            .get(vi)
            .ok_or_else(|| format!("accessor {ai}: buffer view {vi} does not exist"))?;
        let data = self.view_bytes(vi, view)?;
        let stride = view.byte_stride.map(|s| s.0).unwrap_or(elem);
        if stride < elem {
            return Err(format!(
                "accessor {ai}: byte stride {stride} is smaller than the element size {elem}"
            ));
        }
        let start = acc.byte_offset.map(|o| o.0).unwrap_or(0);
        let start =
            usize::try_from(start).map_err(|_| format!("accessor {ai}: offset too large"))?;
        Ok(Strided {
            data,
            start,
            stride,
        })
    }

    /// The bytes of buffer view `vi`: decoded when it is meshopt-compressed, else its range of
    /// its buffer, checked.
    pub(super) fn view_bytes(&self, vi: usize, view: &json::buffer::View) -> Result<&[u8], String> {
        if let Some(Some(decoded)) = self.decoded.get(vi) {
            return Ok(decoded);
        }
        let bi = view.buffer.value();
        if self.buffers.get(bi).is_some_and(|b| b.is_empty())
            && self
                .root
                .buffers
                .get(bi)
                .is_some_and(super::meshopt::is_fallback)
        {
            return Err(format!(
                "buffer view {vi} is not compressed but reads meshopt fallback buffer {bi}, \
                 which holds no data"
            ));
        }
        let buf = self.buffers.get(bi).ok_or_else(|| {
            format!("buffer view {vi}: buffer {bi} does not exist (missing buffer)")
        })?;
        let off = view.byte_offset.map(|o| o.0).unwrap_or(0);
        let len = view.byte_length.0;
        let end = off.checked_add(len);
        match end {
            Some(e) if e <= buf.len() as u64 => Ok(&buf[off as usize..e as usize]),
            _ => Err(format!(
                "buffer view {vi} (offset {off}, length {len}) exceeds buffer {bi} of {} bytes",
                buf.len()
            )),
        }
    }

    /// Read accessor `ai` as floats (`want` components) or unsigned integers.
    pub(super) fn read_accessor(
        &self,
        ai: usize,
        want_uint: bool,
    ) -> Result<(AccessorData, usize), String> {
        let (acc, strided, _elem) = self.locate(ai)?;
        let (Checked::Valid(ty), Checked::Valid(ct)) = (acc.type_, acc.component_type) else {
            return Err(format!("accessor {ai} has an invalid type"));
        };
        let el = Elements {
            ai,
            strided,
            count: acc.count.0 as usize,
            comps: type_comps(ty),
            ct: ct.0,
            normalized: acc.normalized,
        };
        let mut data = if want_uint {
            AccessorData::Uint(el.uints()?)
        } else {
            AccessorData::Float(el.floats()?)
        };
        if let Some(sp) = &acc.sparse {
            self.apply_sparse(&el, sp, &mut data)?;
        }
        Ok((data, el.comps))
    }

    /// Substitute the sparse values `sp` into the decoded elements `data` of accessor `el`.
    fn apply_sparse(
        &self,
        el: &Elements,
        sp: &json::accessor::sparse::Sparse,
        data: &mut AccessorData,
    ) -> Result<(), String> {
        let (ai, count, comps, ct, normalized) = (el.ai, el.count, el.comps, el.ct, el.normalized);
        let n = sp.count.0;
        if n > count as u64 {
            return Err(format!(
                "accessor {ai}: sparse count {n} exceeds count {count}"
            ));
        }
        let n = n as usize;
        let Checked::Valid(ict) = sp.indices.component_type else {
            return Err(format!("accessor {ai}: invalid sparse index type"));
        };
        let get_view = |vi: usize| -> Result<&[u8], String> {
            let v =
                self.root.buffer_views.get(vi).ok_or_else(|| {
                    format!("accessor {ai}: sparse buffer view {vi} does not exist")
                })?;
            self.view_bytes(vi, v)
        };
        let ib = get_view(sp.indices.buffer_view.value())?;
        let io = sp.indices.byte_offset.0 as usize;
        let vb = get_view(sp.values.buffer_view.value())?;
        let vo = sp.values.byte_offset.0 as usize;
        let ics = comp_size(ict.0);
        let cs = comp_size(ct);
        let bad = || format!("accessor {ai}: sparse data out of bounds");
        for s in 0..n {
            let idx = read_uint(ib, io + s * ics, ict.0).ok_or_else(bad)? as usize;
            if idx >= count {
                return Err(format!("accessor {ai}: sparse index {idx} out of range"));
            }
            for k in 0..comps {
                let at = vo + (s * comps + k) * cs;
                match data {
                    AccessorData::Float(v) => {
                        v[idx * comps + k] = read_comp(vb, at, ct, normalized).ok_or_else(bad)?
                    }
                    AccessorData::Uint(v) => {
                        v[idx * comps + k] = read_uint(vb, at, ct).ok_or_else(bad)?
                    }
                }
            }
        }
        Ok(())
    }

    pub(super) fn read_floats(
        &self,
        ai: usize,
        comps: usize,
        what: &str,
    ) -> Result<Vec<f32>, String> {
        let (data, c) = self.read_accessor(ai, false)?;
        if c != comps {
            return Err(format!(
                "{what} accessor {ai} has {c} components, expected {comps}"
            ));
        }
        match data {
            AccessorData::Float(v) => Ok(v),
            AccessorData::Uint(_) => Err(format!("{what} accessor {ai} is not float")),
        }
    }
}
