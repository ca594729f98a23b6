//! [`Kernel`]: the integrator module's entry points.

use super::Specialization;

/// The entry points of the integrator module.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kernel {
    /// Camera paths (`render`): path tracing, plus folding light-tracing splats into the film.
    Render,
    /// Light subpaths connected to the camera (`light_trace`, only with `light_tracing`).
    LightTrace,
    /// Caustic photons stored in the hash grid (`photon_trace`, only with `sppm`).
    PhotonTrace,
    /// `render` as a wavefront (wavefront.wgsl, with `Specialization::wavefront`): camera
    /// rays, then per bounce closest hits, next-event estimates, the rest of the vertex and
    /// the estimates' shadow rays, then the film.
    WfStart,
    WfExtend,
    WfNee,
    WfShade,
    WfConnect,
    WfFinish,
    /// Between a wavefront's bounces (camera or light): the next queue of live paths made
    /// the running one, its dispatch size written.
    WfAdvance,
    /// `light_trace` as a wavefront (light_wavefront.wgsl, lt+pt with
    /// `Specialization::wavefront`): subpath starts, per bounce closest hits, vertices and
    /// camera connections' shadow rays (splats), then the rejected count.
    LtWfStart,
    LtWfExtend,
    LtWfShade,
    LtWfSplat,
    LtWfFinish,
}

impl Kernel {
    /// Every kernel of the integrator module.
    pub const ALL: [Kernel; 15] = [
        Kernel::Render,
        Kernel::LightTrace,
        Kernel::PhotonTrace,
        Kernel::WfStart,
        Kernel::WfExtend,
        Kernel::WfNee,
        Kernel::WfShade,
        Kernel::WfConnect,
        Kernel::WfFinish,
        Kernel::WfAdvance,
        Kernel::LtWfStart,
        Kernel::LtWfExtend,
        Kernel::LtWfShade,
        Kernel::LtWfSplat,
        Kernel::LtWfFinish,
    ];

    /// The WGSL entry point's name.
    pub fn entry(self) -> &'static str {
        match self {
            Kernel::Render => "render",
            Kernel::LightTrace => "light_trace",
            Kernel::PhotonTrace => "photon_trace",
            Kernel::WfStart => "wf_start",
            Kernel::WfExtend => "wf_extend",
            Kernel::WfNee => "wf_nee",
            Kernel::WfShade => "wf_shade",
            Kernel::WfConnect => "wf_connect",
            Kernel::WfFinish => "wf_finish",
            Kernel::WfAdvance => "wf_advance",
            Kernel::LtWfStart => "lt_wf_start",
            Kernel::LtWfExtend => "lt_wf_extend",
            Kernel::LtWfShade => "lt_wf_shade",
            Kernel::LtWfSplat => "lt_wf_splat",
            Kernel::LtWfFinish => "lt_wf_finish",
        }
    }
}

/// The kernels `spec` runs (light tracing only with `light_tracing`, photons only with `sppm`).
pub fn kernels_of(spec: &Specialization) -> Vec<Kernel> {
    Kernel::ALL
        .into_iter()
        .filter(|k| match k {
            Kernel::Render => !spec.wavefront,
            Kernel::LightTrace => spec.light_tracing && !spec.wavefront,
            Kernel::PhotonTrace => spec.sppm,
            Kernel::LtWfStart
            | Kernel::LtWfExtend
            | Kernel::LtWfShade
            | Kernel::LtWfSplat
            | Kernel::LtWfFinish => spec.light_tracing && spec.wavefront,
            _ => spec.wavefront,
        })
        .collect()
}
