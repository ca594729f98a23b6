//! The density estimate at a camera path's diffuse vertex: the photons of one iteration
//! within radius r, each weighted by the BSDF, over the disk area π r² and the number of
//! photon paths traced (Jensen 1996, eq. 8; Hachisuka et al. 2008, eq. 5).

use super::grid::HashGrid;
use super::photon::Photon;
use crate::bsdf::{Bsdf, BxDF, TransportMode};
use crate::cpu::gather::Gather;
use crate::cpu::interaction::Interaction;
use crate::cpu::path_state::PathState;
use crate::cpu::spectral::Spectral;
use crate::math::Color;
use crate::paths::{DfaTable, Symbol};

use crate::render::photon_params::SAME_SURFACE_COS;

/// One iteration's photons, ready for queries.
pub struct PhotonLookup<'a> {
    pub photons: &'a [Photon],
    pub grid: &'a HashGrid,
    /// 1 / (photon paths traced · π r²).
    pub norm: f32,
    pub max_depth: u32,
    /// Heckbert filter in eye→light order (`PathFilter::reversed`).
    pub filter: Option<&'a DfaTable>,
    /// The environment is in the light distribution (so it emits photons).
    pub env_emits: bool,
}

impl PhotonLookup<'_> {
    /// Bit k set: the string D S^k L read from state `q` is accepted by the filter.
    fn accepted_chains(&self, q: u32) -> u64 {
        let Some(f) = self.filter else {
            return u64::MAX;
        };
        let mut mask = 0u64;
        let mut s = f.step(q, Symbol::D);
        for k in 1..64 {
            s = f.step(s, Symbol::S);
            if f.is_accepting(f.step(s, Symbol::L)) {
                mask |= 1 << k;
            }
        }
        mask
    }

    /// Is D S^k L from `q` accepted (bit k of `chains`, or walked for k ≥ 64)?
    #[inline]
    fn chain_accepted(&self, chains: u64, q: u32, k: u32) -> bool {
        match self.filter {
            None => true,
            Some(_) if k < 64 => chains & (1 << k) != 0,
            Some(f) => {
                let mut s = f.step(q, Symbol::D);
                for _ in 0..k {
                    s = f.step(s, Symbol::S);
                }
                f.is_accepting(f.step(s, Symbol::L))
            }
        }
    }
}

impl Gather for PhotonLookup<'_> {
    /// Reads depth, collapse and the vertex geometry only, never media or uv.
    const READS_STATE: bool = false;

    fn gather(&self, it: &Interaction, st: &PathState, q: u32, _sp: &Spectral) -> Option<Color> {
        if !matches!(it.bsdf, Bsdf::Lambert(_)) || st.depth + 3 > self.max_depth {
            return None;
        }
        let chains = self.accepted_chains(q);
        let x = it.hit.p;
        let r2 = self.grid.radius2();
        let mut sum = Color::ZERO;
        self.grid.candidates(x, |i| {
            let ph = &self.photons[i as usize];
            if ph.p.distance_squared(x) > r2
                || !self.chain_accepted(chains, q, ph.specular)
                || st.depth + ph.specular + 2 > self.max_depth
                || ph.ng.dot(it.ng) < SAME_SURFACE_COS
            {
                return;
            }
            let cos_g = ph.wi.dot(it.ng);
            if cos_g <= 0.0 {
                return;
            }
            let f = it
                .bsdf
                .eval(it.wo, it.frame.to_local(ph.wi), TransportMode::Radiance);
            // dΦ/dA counts cosθ against the geometric normal, the BSDF integral the shading
            // normal's (Veach 1997, eq. 5.19's correction at the gather vertex).
            let corr = ph.wi.dot(it.ns).abs() / cos_g;
            // After a collapse only the hero lane lives and stands for ¼ of the estimate;
            // the ×4 is applied once per full path (the camera side's `weight` has it if
            // the camera path collapsed too).
            let w = if ph.collapsed && !st.collapsed {
                4.0
            } else {
                1.0
            };
            sum += f * ph.beta * (corr * w);
        });
        Some(sum * self.norm)
    }

    fn environment_emits(&self) -> bool {
        self.env_emits
    }
}
