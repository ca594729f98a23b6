//! The binary side of a .glb: [`Buffers`] (the BIN chunk with its buffer views and
//! accessors) and [`glb`], the container that wraps the JSON and BIN chunks.

use glam::Vec3;
use serde_json::{Value, json};

/// The binary chunk with its buffer views and accessors, filled in order.
#[derive(Default)]
pub(super) struct Buffers {
    pub(super) bin: Vec<u8>,
    pub(super) views: Vec<Value>,
    pub(super) accessors: Vec<Value>,
}

impl Buffers {
    /// Append `bytes` (4-byte aligned) as a buffer view + accessor; returns the accessor index.
    pub(super) fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        ty: &str,
        ctype: u32,
        target: u32,
        minmax: Option<(Vec3, Vec3)>,
    ) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let view = self.views.len();
        self.views.push(json!({
            "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len(), "target": target
        }));
        self.bin.extend_from_slice(bytes);
        let mut acc = json!({
            "bufferView": view, "componentType": ctype, "count": count, "type": ty
        });
        if let Some((lo, hi)) = minmax {
            acc["min"] = json!(lo.to_array());
            acc["max"] = json!(hi.to_array());
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }
}

/// Wrap JSON and binary chunks into a GLB container (glTF 2.0 §4.4).
pub(super) fn glb(json_bytes: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut js = json_bytes.to_vec();
    while !js.len().is_multiple_of(4) {
        js.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + js.len() + if b.is_empty() { 0 } else { 8 + b.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(js.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&js);
    if !b.is_empty() {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&b);
    }
    out
}
