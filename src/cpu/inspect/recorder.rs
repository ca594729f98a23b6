//! The observer that turns the camera walk's hooks into `PathRecord`s. Every number comes
//! from what the step itself used: the media of `PathState` for η_i and η_t, the BSDF
//! sample's event, lobe, direction and selection probability for the event, cos θ_t and F.

use super::record::{
    ConnectionRecord, PathRecord, ScatterRecord, VertexEvent, VertexRecord, heckbert_string,
};
use crate::bsdf::fresnel::cos2_transmitted;
use crate::bsdf::{Bsdf, BsdfSample, Event, Lobe, TransportMode};
use crate::cpu::interaction::{Interaction, SurfaceHit};
use crate::cpu::medium::medium_ior;
use crate::cpu::observer::{PathEnd, PathObserver};
use crate::cpu::path_state::PathState;
use crate::cpu::spectral::Spectral;
use crate::math::Color;
use crate::paths::Symbol;
use crate::scene::Scene;
use crate::scene::light::LiSample;
use glam::Vec3;

/// Records one camera path.
pub struct Recorder {
    /// Scene diameter: how far to place a vertex "at infinity" for drawing.
    extent: f32,
    sp: Spectral,
    /// Direction of the segment being travelled.
    dir: Vec3,
    path: PathRecord,
}

impl Recorder {
    pub fn new(extent: f32) -> Recorder {
        Recorder {
            extent,
            sp: Spectral::RGB,
            dir: Vec3::ZERO,
            path: PathRecord {
                heckbert: String::new(),
                contribution: [0.0; 3],
                vertices: Vec::new(),
                connections: Vec::new(),
                end: PathEnd::Terminated,
                escape_dir: None,
                lambda_nm: None,
            },
        }
    }

    /// The finished record; `estimate` is what the walk returned for the sample.
    pub fn finish(mut self, estimate: Vec3) -> PathRecord {
        self.path.contribution = estimate.to_array();
        self.path.heckbert = heckbert_string(&self.path.vertices);
        self.path
    }

    fn rgb(&self, c: Color) -> [f32; 3] {
        self.sp.to_rgb(c).to_array()
    }

    fn last(&mut self) -> Option<&mut VertexRecord> {
        self.path.vertices.last_mut()
    }
}

/// The Heckbert class a next-event connection at `it` towards local `wi` goes through: the
/// BSDF's class, or for the two-lobe metal-rough BRDF the lobe carrying more of f.
fn connection_class(it: &Interaction, wi: Vec3) -> Symbol {
    if let Bsdf::MetalRough(_) = it.bsdf {
        let lv = it.bsdf.eval_lobes(it.wo, wi, TransportMode::Radiance);
        return if lv.d.max_element() >= lv.g.max_element() {
            Symbol::D
        } else {
            Symbol::G
        };
    }
    Symbol::from(it.bsdf.class())
}

/// |cos θ| of a local-frame direction against the shading normal (z). The walk's directions
/// drift from unit length by a few ulps per bounce; the cosine of the direction itself is
/// what Snell's law relates.
fn abs_cos(w: Vec3) -> f32 {
    (w.z / w.length()).abs().min(1.0)
}

/// The event of the BSDF sample `s` at `it` and, at a smooth or thin dielectric, the
/// reflectance F the step chose it with. The inspector's classification, shared with the
/// event heatmaps (`cpu::aov`).
pub fn sample_event(it: &Interaction, s: &BsdfSample) -> (VertexEvent, Option<f32>) {
    let dielectric = matches!(it.bsdf, Bsdf::SmoothDielectric(_) | Bsdf::ThinDielectric(_));
    match s.lobe {
        Lobe::D => (VertexEvent::Diffuse, None),
        Lobe::G => (VertexEvent::Glossy, None),
        Lobe::S if !dielectric => (VertexEvent::Reflect, None),
        Lobe::S => {
            // Delta dielectric lobes are picked with probability F (reflect) or 1 − F.
            let f = match s.event {
                Event::Reflect => s.pdf,
                Event::Transmit => 1.0 - s.pdf,
            };
            let event = match s.event {
                Event::Transmit => VertexEvent::Refract,
                Event::Reflect if f >= 1.0 => VertexEvent::Tir,
                Event::Reflect => VertexEvent::Reflect,
            };
            (event, Some(f))
        }
    }
}

/// Event, |cos θ_t| and F of the sample `s` at `it` for the IORs `(eta_i, eta_t)`.
fn classify(
    it: &Interaction,
    s: &BsdfSample,
    (eta_i, eta_t): (f32, f32),
) -> (VertexEvent, f32, Option<f32>) {
    let (event, fresnel) = sample_event(it, s);
    let cos_t = match (fresnel, s.event) {
        // The refracted sibling's cosine (Snell, PBR 4th ed. §9.3.2); 0 under TIR.
        (Some(_), Event::Reflect) => {
            let c2 = cos2_transmitted(abs_cos(it.wo), eta_t / eta_i);
            c2.max(0.0).sqrt()
        }
        _ => abs_cos(s.wi),
    };
    (event, cos_t, fresnel)
}

impl PathObserver for Recorder {
    fn start(&mut self, origin: Vec3, dir: Vec3, sp: &Spectral) {
        self.sp = *sp;
        self.dir = dir;
        self.path.lambda_nm = sp.lambdas;
        self.path.vertices.push(VertexRecord {
            p: origin.to_array(),
            class: Symbol::E,
            event: VertexEvent::Camera,
            material: "camera".to_owned(),
            eta_i: 1.0,
            eta_t: 1.0,
            cos_i: None,
            cos_t: None,
            fresnel: None,
            throughput: [1.0; 3],
            emitted: None,
            step_eta_rel: None,
            scatter: None,
        });
    }

    fn surface(&mut self, scene: &Scene, hit: &SurfaceHit, st: &PathState) {
        let mat = &scene.materials[hit.material as usize];
        let class = Symbol::from(mat.bsdf(&scene.textures, hit.uv, mat.ior).class());
        let eta = medium_ior(scene, st.medium(scene), &self.sp);
        let throughput = self.rgb(st.weight());
        self.path.vertices.push(VertexRecord {
            p: hit.p.to_array(),
            class,
            event: VertexEvent::Absorbed,
            material: mat.name.clone(),
            eta_i: eta,
            eta_t: eta,
            cos_i: Some(self.dir.normalize_or_zero().dot(hit.ns).abs().min(1.0)),
            cos_t: None,
            fresnel: None,
            throughput,
            emitted: None,
            step_eta_rel: None,
            scatter: None,
        });
    }

    fn emitted(&mut self, contribution: Color) {
        let c = self.rgb(contribution);
        if let Some(v) = self.last() {
            v.class = Symbol::L;
            v.event = VertexEvent::Emission;
            v.emitted = Some(c);
        }
    }

    fn connection(&mut self, it: &Interaction, ls: &LiSample, contribution: Color, occluded: bool) {
        let Some(from) = self.path.vertices.len().checked_sub(1) else {
            return;
        };
        let class = connection_class(it, it.frame.to_local(ls.wi));
        let before = heckbert_string(&self.path.vertices[..from]);
        let p = if ls.infinite {
            it.hit.p + ls.wi * self.extent
        } else {
            ls.p_light
        };
        let rec = ConnectionRecord {
            from,
            p: p.to_array(),
            heckbert: format!("L{}{before}", class.as_char()),
            contribution: self.rgb(contribution),
            occluded,
            at_infinity: ls.infinite,
        };
        self.path.connections.push(rec);
    }

    fn bounce(
        &mut self,
        scene: &Scene,
        it: &Interaction,
        st: &PathState,
        s: &BsdfSample,
        wi: Vec3,
    ) {
        let eta_i = medium_ior(scene, st.medium(scene), &self.sp);
        // The medium across the surface: the one a transmission along wi enters (for a
        // reflection, the one its refracted sibling would have entered).
        let across = if s.event == Event::Transmit {
            wi
        } else {
            -it.wo_w
        };
        let eta_t = medium_ior(scene, st.medium_towards(scene, it, across), &self.sp);
        let (event, cos_t, fresnel) = classify(it, s, (eta_i, eta_t));
        self.dir = wi;
        let spectral = self.sp.lambdas.is_some();
        if let Some(v) = self.last() {
            v.class = Symbol::from(s.lobe);
            v.event = event;
            v.eta_i = eta_i;
            v.eta_t = eta_t;
            v.cos_i = Some(abs_cos(it.wo));
            v.cos_t = Some(cos_t);
            v.fresnel = fresnel;
            v.step_eta_rel = Some(s.eta_rel);
            v.scatter = Some(ScatterRecord {
                bsdf: it.bsdf,
                wo: it.wo,
                spectral,
            });
        }
    }

    fn throughput(&mut self, weight: Color) {
        let c = self.rgb(weight);
        if let Some(v) = self.last() {
            v.throughput = c;
        }
    }

    fn escaped(&mut self, dir: Vec3, contribution: Color) {
        if contribution.max_element() <= 0.0 {
            return;
        }
        let from = self
            .path
            .vertices
            .last()
            .map_or(Vec3::ZERO, |v| Vec3::from(v.p));
        let throughput = self.path.vertices.last().map_or([1.0; 3], |v| v.throughput);
        let emitted = Some(self.rgb(contribution));
        self.path.vertices.push(VertexRecord {
            p: (from + dir * self.extent).to_array(),
            class: Symbol::L,
            event: VertexEvent::Emission,
            material: "environment".to_owned(),
            eta_i: 1.0,
            eta_t: 1.0,
            cos_i: None,
            cos_t: None,
            fresnel: None,
            throughput,
            emitted,
            step_eta_rel: None,
            scatter: None,
        });
    }

    fn end(&mut self, why: PathEnd) {
        self.path.end = why;
        if why == PathEnd::Escaped {
            self.path.escape_dir = Some(self.dir.to_array());
        }
    }
}
