//! [`MainLight`]: which emitter is a scene's main area light, and where it sits (the light
//! edit's size and placement act on it).

use crate::math::color::luminance;
use crate::scene::Scene;
use glam::Vec3;

/// Facts about the main area light of a scene (the emitter material with the most power).
#[derive(Clone, Debug)]
pub struct MainLight {
    pub material: usize,
    pub triangles: Vec<u32>,
    /// Area-weighted centroid of its triangles.
    pub centroid: Vec3,
    /// Scene bounding-box centre: the light is placed on a sphere around it.
    pub centre: Vec3,
    pub elevation_deg: f32,
    pub azimuth_deg: f32,
}

impl MainLight {
    pub fn find(scene: &Scene) -> Option<MainLight> {
        let mut power = vec![0.0f32; scene.materials.len()];
        for t in scene.emissive_triangles() {
            let mi = scene.mesh.tri_material[t as usize] as usize;
            power[mi] += luminance(scene.materials[mi].emission) * scene.mesh.area(t as usize);
        }
        let (material, &p) = power.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
        if p.is_nan() || p <= 0.0 {
            return None;
        }
        let triangles: Vec<u32> = (0..scene.mesh.triangle_count() as u32)
            .filter(|&t| scene.mesh.tri_material[t as usize] as usize == material)
            .collect();
        let mut area = 0.0f32;
        let mut c = Vec3::ZERO;
        for &t in &triangles {
            let [a, b, cc] = scene.mesh.tri(t as usize);
            let ar = scene.mesh.area(t as usize);
            area += ar;
            c += ar * (a + b + cc) / 3.0;
        }
        if area <= 0.0 {
            return None;
        }
        let centroid = c / area;
        let (lo, hi) = scene.bounds();
        let centre = 0.5 * (lo + hi);
        let d = (centroid - centre).normalize_or(Vec3::Y);
        Some(MainLight {
            material,
            triangles,
            centroid,
            centre,
            elevation_deg: d.y.clamp(-1.0, 1.0).asin().to_degrees(),
            azimuth_deg: d.x.atan2(d.z).to_degrees(),
        })
    }
}
