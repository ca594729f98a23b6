//! `EXT_meshopt_compression`: buffer views whose bytes are stored compressed in another buffer
//! (meshoptimizer's vertex and index codecs), decoded once after the buffers are read.
//!
//! The extension (KhronosGroup/glTF, `extensions/2.0/Vendor/EXT_meshopt_compression`) adds to a
//! buffer view `{buffer, byteOffset, byteLength, byteStride, count, mode, filter}`: the view's
//! own `byteLength` bytes are `count × byteStride` bytes decoded from `byteLength` compressed
//! bytes of `buffer`. `mode` picks the codec (`ATTRIBUTES`: vertex codec; `TRIANGLES`: index
//! buffer codec; `INDICES`: index sequence codec) and `filter` a post-pass on decoded
//! attributes (`OCTAHEDRAL` unit vectors, `QUATERNION` rotations, `EXPONENTIAL` floats). The
//! view's own buffer may be a "fallback" buffer with no data at all (`fallback: true`).
//!
//! Decoding is meshoptimizer's (the `meshopt` crate: its decoders are written for untrusted
//! input). Every size and mode the C++ decoders assert on is checked here first, so a hostile
//! file gets an error naming the view, never an abort.

use crate::text::abbreviate;
use gltf::json;
use serde_json::Value;

/// The extension's name, as it appears in the JSON.
pub(super) const EXT: &str = "EXT_meshopt_compression";

/// Largest `byteStride` of the vertex codec (meshoptimizer's limit, and the extension's).
const MAX_VERTEX_STRIDE: u64 = 256;

/// Whether buffer `b` is a meshopt fallback buffer (it may have no URI and no data).
pub(super) fn is_fallback(b: &json::Buffer) -> bool {
    b.extensions
        .as_ref()
        .and_then(|e| e.others.get(EXT))
        .and_then(|v| v.get("fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// The decoded bytes of every compressed buffer view (None: the view is not compressed).
pub(super) fn decode_views(
    root: &json::Root,
    buffers: &[Vec<u8>],
) -> Result<Vec<Option<Vec<u8>>>, String> {
    root.buffer_views
        .iter()
        .enumerate()
        .map(|(vi, view)| {
            let ext = view.extensions.as_ref().and_then(|e| e.others.get(EXT));
            ext.map(|ext| decode_view(vi, view, ext, buffers))
                .transpose()
        })
        .collect()
}

/// One compressed view's extension object, parsed and checked.
struct Compressed<'a> {
    source: &'a [u8],
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
}

/// Decode view `vi` from its extension object `ext`.
fn decode_view(
    vi: usize,
    view: &json::buffer::View,
    ext: &Value,
    buffers: &[Vec<u8>],
) -> Result<Vec<u8>, String> {
    let c = parse(vi, ext, buffers).map_err(|e| format!("buffer view {vi}: {EXT}: {e}"))?;
    let out_len = c.stride * c.count;
    if out_len as u64 != view.byte_length.0 {
        return Err(format!(
            "buffer view {vi}: {EXT}: count {} × byteStride {} = {out_len} bytes, but the view's \
             byteLength is {}",
            c.count, c.stride, view.byte_length.0
        ));
    }
    c.decode()
        .map_err(|e| format!("buffer view {vi}: {EXT} data does not decode ({e})"))
}

/// The extension object's fields, each checked against the codec's limits.
fn parse<'a>(_vi: usize, ext: &Value, buffers: &'a [Vec<u8>]) -> Result<Compressed<'a>, String> {
    let int = |k: &str| -> Result<u64, String> {
        ext.get(k)
            .and_then(Value::as_u64)
            .ok_or_else(|| format!("'{k}' is missing or not a non-negative integer"))
    };
    let opt_int = |k: &str| -> Result<u64, String> {
        match ext.get(k) {
            None => Ok(0),
            Some(_) => int(k),
        }
    };
    let bi = int("buffer")?;
    let buf = usize::try_from(bi)
        .ok()
        .and_then(|b| buffers.get(b))
        .ok_or_else(|| format!("buffer {bi} does not exist"))?;
    let (off, len) = (opt_int("byteOffset")?, int("byteLength")?);
    let source = off
        .checked_add(len)
        .filter(|&end| end <= buf.len() as u64)
        .map(|end| &buf[off as usize..end as usize])
        .ok_or_else(|| {
            format!(
                "byteOffset {off} + byteLength {len} exceed buffer {bi} of {} bytes",
                buf.len()
            )
        })?;
    let mode = parse_mode(ext.get("mode"))?;
    let filter = parse_filter(ext.get("filter"))?;
    let (stride, count) = (int("byteStride")?, int("count")?);
    check_shape(mode, filter, stride, count)?;
    Ok(Compressed {
        source,
        stride: stride as usize,
        count: count as usize,
        mode,
        filter,
    })
}

fn parse_mode(v: Option<&Value>) -> Result<Mode, String> {
    match v.and_then(Value::as_str) {
        Some("ATTRIBUTES") => Ok(Mode::Attributes),
        Some("TRIANGLES") => Ok(Mode::Triangles),
        Some("INDICES") => Ok(Mode::Indices),
        Some(m) => Err(format!("unknown mode '{}'", abbreviate(m))),
        None => Err("'mode' is missing".into()),
    }
}

fn parse_filter(v: Option<&Value>) -> Result<Filter, String> {
    match v.map(|v| v.as_str()) {
        None | Some(Some("NONE")) => Ok(Filter::None),
        Some(Some("OCTAHEDRAL")) => Ok(Filter::Octahedral),
        Some(Some("QUATERNION")) => Ok(Filter::Quaternion),
        Some(Some("EXPONENTIAL")) => Ok(Filter::Exponential),
        Some(Some(f)) => Err(format!("unknown filter '{}'", abbreviate(f))),
        Some(None) => Err("'filter' is not a string".into()),
    }
}

/// The stride/count/filter combinations the extension allows (and meshoptimizer asserts on).
fn check_shape(mode: Mode, filter: Filter, stride: u64, count: u64) -> Result<(), String> {
    let ok = match mode {
        Mode::Attributes => stride > 0 && stride <= MAX_VERTEX_STRIDE && stride.is_multiple_of(4),
        Mode::Triangles | Mode::Indices => stride == 2 || stride == 4,
    };
    if !ok {
        return Err(format!(
            "byteStride {stride} is not allowed for mode {mode:?}"
        ));
    }
    if mode == Mode::Triangles && !count.is_multiple_of(3) {
        return Err(format!(
            "count {count} of mode TRIANGLES is not a multiple of 3"
        ));
    }
    if mode != Mode::Attributes && filter != Filter::None {
        return Err(format!(
            "filter {filter:?} is only allowed with mode ATTRIBUTES"
        ));
    }
    let filter_ok = match filter {
        Filter::None => true,
        Filter::Octahedral => stride == 4 || stride == 8,
        Filter::Quaternion => stride == 8,
        Filter::Exponential => stride.is_multiple_of(4),
    };
    if !filter_ok {
        return Err(format!(
            "filter {filter:?} does not allow byteStride {stride}"
        ));
    }
    // The decoded view must fit in memory and in an accessor (its byteLength is checked against
    // this product by the caller, and buffers' byteLength against the file size limit).
    stride
        .checked_mul(count)
        .filter(|&n| usize::try_from(n).is_ok())
        .map(|_| ())
        .ok_or_else(|| format!("count {count} × byteStride {stride} overflows"))
}

impl Compressed<'_> {
    /// The view's `count × stride` bytes.
    fn decode(&self) -> Result<Vec<u8>, meshopt::Error> {
        match self.mode {
            Mode::Attributes => self.decode_attributes(),
            Mode::Triangles | Mode::Indices => self.decode_indices(),
        }
    }

    /// Vertex codec, then the filter in place, in 4-byte words (meshoptimizer's filters read
    /// 16- and 32-bit lanes, so the words keep them aligned).
    fn decode_attributes(&self) -> Result<Vec<u8>, meshopt::Error> {
        let mut words = vec![0u32; self.count * self.stride / 4];
        if self.count > 0 {
            // SAFETY: `words` holds exactly `count × stride` writable bytes (stride is a multiple
            // of 4, checked in `check_shape`), which is what meshopt_decodeVertexBuffer writes;
            // stride is in (0, 256] and a multiple of 4, as the decoder requires, and it reads
            // at most `source.len()` bytes of `source` (it is written for untrusted input).
            let rc = unsafe {
                meshopt::ffi::meshopt_decodeVertexBuffer(
                    words.as_mut_ptr().cast(),
                    self.count,
                    self.stride,
                    self.source.as_ptr(),
                    self.source.len(),
                )
            };
            if rc != 0 {
                return Err(meshopt::Error::Native(rc));
            }
        }
        self.apply_filter(&mut words);
        Ok(bytemuck::cast_slice(&words).to_vec())
    }

    fn apply_filter(&self, words: &mut [u32]) {
        match (self.filter, self.stride) {
            (Filter::None, _) => {}
            (Filter::Octahedral, 4) => {
                meshopt::decode_filter_oct::<i8>(bytemuck::cast_slice_mut(words));
            }
            (Filter::Octahedral | Filter::Quaternion, _) => {
                let lanes: &mut [[i16; 4]] = bytemuck::cast_slice_mut(words);
                if self.filter == Filter::Octahedral {
                    meshopt::decode_filter_oct::<i16>(lanes);
                } else {
                    meshopt::decode_filter_quat(lanes);
                }
            }
            // Each 32-bit component is decoded on its own, whatever the stride.
            (Filter::Exponential, _) => {
                meshopt::decode_filter_exp::<1>(bytemuck::cast_slice_mut(words));
            }
        }
    }

    /// Index buffer (TRIANGLES) or index sequence (INDICES) codec, at 2 or 4 bytes an index.
    fn decode_indices(&self) -> Result<Vec<u8>, meshopt::Error> {
        let (src, n) = (self.source, self.count);
        let tri = self.mode == Mode::Triangles;
        Ok(match self.stride {
            2 => {
                let v: Vec<u16> = if tri {
                    meshopt::decode_index_buffer(src, n)?
                } else {
                    meshopt::decode_index_sequence(src, n)?
                };
                v.iter().flat_map(|i| i.to_le_bytes()).collect()
            }
            _ => {
                let v: Vec<u32> = if tri {
                    meshopt::decode_index_buffer(src, n)?
                } else {
                    meshopt::decode_index_sequence(src, n)?
                };
                v.iter().flat_map(|i| i.to_le_bytes()).collect()
            }
        })
    }
}
