//! The path inspector's readable output (`refract trace` without `--json`).

use super::record::{PathRecord, PixelTrace, VertexRecord};
use std::fmt::Write;

/// Every path of `trace` as a table of its vertices and connections.
pub fn format_table(trace: &PixelTrace) -> String {
    let mut out = String::new();
    let [x, y] = trace.pixel;
    let _ = writeln!(
        out,
        "pixel ({x}, {y}) of {}x{}, seed {}: {} paths, mean {}",
        trace.width,
        trace.height,
        trace.seed,
        trace.paths.len(),
        rgb(trace.mean)
    );
    for (i, p) in trace.paths.iter().enumerate() {
        path_table(&mut out, i, p);
    }
    out
}

fn path_table(out: &mut String, i: usize, p: &PathRecord) {
    let _ = writeln!(
        out,
        "\npath {i}: {}  contribution {}  end {}",
        p.heckbert,
        rgb(p.contribution),
        p.end.as_str()
    );
    let _ = writeln!(
        out,
        "  {:>2} {:<2} {:<8} {:<14} {:>13} {:>7} {:>7} {:>7}  {:<24} position",
        "#", "cl", "event", "material", "η_i → η_t", "θ_i°", "θ_t°", "F", "throughput"
    );
    for (k, v) in p.vertices.iter().enumerate() {
        vertex_row(out, k, v);
    }
    for c in &p.connections {
        let _ = writeln!(
            out,
            "  ╌╌ light connection from #{}: {}  {}{}  light at {}",
            c.from,
            c.heckbert,
            rgb(c.contribution),
            if c.occluded { "  (occluded)" } else { "" },
            vec3(c.p)
        );
    }
}

fn vertex_row(out: &mut String, k: usize, v: &VertexRecord) {
    let deg = |c: Option<f32>| {
        c.map_or("—".to_owned(), |c| {
            format!("{:.2}", c.clamp(0.0, 1.0).acos().to_degrees())
        })
    };
    let event = format!("{:?}", v.event).to_lowercase();
    let _ = writeln!(
        out,
        "  {k:>2} {:<2} {event:<8} {:<14} {:>13} {:>7} {:>7} {:>7}  {:<24} {}",
        v.class.as_char(),
        truncate(&v.material, 14),
        format!("{:.4} → {:.4}", v.eta_i, v.eta_t),
        deg(v.cos_i),
        deg(v.cos_t),
        v.fresnel.map_or("—".to_owned(), |f| format!("{f:.4}")),
        rgb(v.throughput),
        vec3(v.p)
    );
}

fn truncate(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_owned()
    } else {
        let mut t: String = s.chars().take(n - 1).collect();
        t.push('…');
        t
    }
}

fn rgb(c: [f32; 3]) -> String {
    format!("({:.4}, {:.4}, {:.4})", c[0], c[1], c[2])
}

fn vec3(p: [f32; 3]) -> String {
    format!("({:.3}, {:.3}, {:.3})", p[0], p[1], p[2])
}
