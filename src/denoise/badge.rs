//! What a teaching tool must show when it denoises: the split line between the raw image
//! (left) and the denoised one (right), and a "DENOISED" badge in the top-right corner,
//! drawn into RGBA8 pixels so that screenshots carry them too. With denoising off the raw
//! pixels are returned untouched ([`compose`]).

/// 5×7 glyphs of the badge's letters (rows top to bottom, bit 4 = leftmost column).
fn glyph(c: u8) -> [u8; 7] {
    match c {
        b'D' => [0x1e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1e],
        b'E' => [0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x1f],
        b'N' => [0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11],
        b'O' => [0x0e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e],
        b'I' => [0x0e, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e],
        b'S' => [0x0f, 0x10, 0x10, 0x0e, 0x01, 0x01, 0x1e],
        _ => [0; 7],
    }
}

/// The badge's text.
pub const BADGE: &str = "DENOISED";

/// The split column of a `width`-wide image at `split` ∈ [0, 1] (the fraction kept raw).
pub fn split_column(width: u32, split: f32) -> u32 {
    (split.clamp(0.0, 1.0) * width as f32).round() as u32
}

/// The image to show: `raw` when `denoised` is `None`, else raw left of the split column,
/// denoised right of it, a white split line and the badge. RGBA8, row-major, `width` wide.
pub fn compose(raw: &[u8], denoised: Option<&[u8]>, width: u32, split: f32) -> Vec<u8> {
    let Some(den) = denoised else {
        return raw.to_vec();
    };
    assert_eq!(raw.len(), den.len(), "raw and denoised differ in size");
    let w = width.max(1) as usize;
    let col = split_column(width, split) as usize;
    let mut out = raw.to_vec();
    for (i, px) in out.chunks_exact_mut(4).enumerate() {
        if i % w >= col {
            px.copy_from_slice(&den[i * 4..i * 4 + 4]);
        }
    }
    draw_badge(&mut out, width, (raw.len() / 4 / w) as u32);
    // The split line last: on a narrow image it crosses the badge, never the reverse.
    for (i, px) in out.chunks_exact_mut(4).enumerate() {
        let x = i % w;
        if x + 1 == col || x == col {
            px.copy_from_slice(&[255, 255, 255, 255]);
        }
    }
    out
}

/// The badge: white letters on a dark box in the top-right corner (scaled ×2 on images
/// at least 400 pixels wide; left out on images too small to hold it).
pub fn draw_badge(px: &mut [u8], width: u32, height: u32) {
    let scale = if width >= 400 { 2 } else { 1 };
    let (cw, pad) = (6 * scale, 2 * scale);
    let bw = BADGE.len() as u32 * cw + 2 * pad;
    let bh = 7 * scale + 2 * pad;
    if bw + 4 > width || bh + 4 > height {
        return;
    }
    let (x0, y0) = (width - bw - 4, 4);
    let mut put = |x: u32, y: u32, c: [u8; 4]| {
        let i = ((y * width + x) * 4) as usize;
        px[i..i + 4].copy_from_slice(&c);
    };
    for y in 0..bh {
        for x in 0..bw {
            put(x0 + x, y0 + y, [24, 24, 24, 255]);
        }
    }
    for (k, ch) in BADGE.bytes().enumerate() {
        for (row, bits) in glyph(ch).iter().enumerate() {
            for colb in 0..5u32 {
                if bits >> (4 - colb) & 1 == 0 {
                    continue;
                }
                for (sy, sx) in (0..scale).flat_map(|a| (0..scale).map(move |b| (a, b))) {
                    let x = x0 + pad + k as u32 * cw + colb * scale + sx;
                    let y = y0 + pad + row as u32 * scale + sy;
                    put(x, y, [255, 255, 255, 255]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn off_is_the_raw_image_bit_for_bit_and_on_shows_split_and_badge() {
        let (w, h) = (120u32, 40u32);
        let raw: Vec<u8> = (0..w * h * 4).map(|i| (i * 7 % 251) as u8).collect();
        assert_eq!(compose(&raw, None, w, 0.5), raw);
        let den = vec![10u8; raw.len()];
        let out = compose(&raw, Some(&den), w, 0.5);
        let at = |x: u32, y: u32| &out[((y * w + x) * 4) as usize..((y * w + x) * 4 + 4) as usize];
        let raw_at =
            |x: u32, y: u32| &raw[((y * w + x) * 4) as usize..((y * w + x) * 4 + 4) as usize];
        assert_eq!(at(5, 30), raw_at(5, 30), "left of the split is raw");
        assert_eq!(
            at(100, 30),
            &[10, 10, 10, 10],
            "right of the split is denoised"
        );
        assert_eq!(at(60, 30), &[255, 255, 255, 255], "the split line");
        let badge = (0..16).flat_map(|y| (60..w).map(move |x| (x, y)));
        assert!(badge.clone().any(|(x, y)| at(x, y) == [24, 24, 24, 255]));
        assert!(badge.clone().any(|(x, y)| at(x, y) == [255, 255, 255, 255]));
    }
}
