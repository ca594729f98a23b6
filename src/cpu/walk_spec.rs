//! Which of a scene's features an instance of the camera walk is compiled for (issue 14
//! part 2): the walk (`Integrator::li_walk`) is generic over a [`WalkSpec`], whose flags are
//! upper bounds known at compile time. A `false` flag removes that feature's code from the
//! instance (the way `gpu::pipeline` compiles absent features out of its shaders); a
//! `true` flag leaves it to the runtime test the walk always made. The instance is chosen
//! once per camera path from the scene's `Features` ([`WalkFeatures::lean`]), so one walk's
//! source serves every scene and the images do not change.

/// Compile-time bounds on the features a camera walk handles.
pub trait WalkSpec {
    /// Hero-wavelength spectral lanes (`Features::DISPERSION`).
    const SPECTRAL: bool;
    /// A Heckbert path filter (`--paths`).
    const FILTER: bool;
    /// A medium stack: nested volumes (`Features::NESTED`) or Beer–Lambert absorption
    /// (`Features::ABSORPTION`). Without either, every interface refracts against air and no
    /// segment attenuates, so the walk keeps no media.
    const MEDIA: bool;
    /// Textured materials (`Features::TEXTURES`): surface hits interpolate uv.
    const TEXTURES: bool;
}

/// The [`WalkSpec`] with the four flags given.
pub struct Spec<const SPECTRAL: bool, const FILTER: bool, const MEDIA: bool, const TEXTURES: bool>;

impl<const S: bool, const F: bool, const M: bool, const T: bool> WalkSpec for Spec<S, F, M, T> {
    const SPECTRAL: bool = S;
    const FILTER: bool = F;
    const MEDIA: bool = M;
    const TEXTURES: bool = T;
}

/// Every feature left to its runtime test (the walk as it was before specialisation).
pub type General = Spec<true, true, true, true>;

/// RGB, unfiltered, no media, no textures (cornell-glass, caustic, glass-slab …).
pub type Lean = Spec<false, false, false, false>;

/// What one camera path needs, from which the walk instance is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WalkFeatures {
    pub spectral: bool,
    pub filter: bool,
    pub media: bool,
    pub textures: bool,
}

impl WalkFeatures {
    /// Nothing the [`Lean`] instance leaves out is needed.
    #[inline]
    pub fn lean(&self) -> bool {
        !(self.spectral || self.filter || self.media || self.textures)
    }

    /// Does the instance `S` handle everything these features need?
    pub fn fits<S: WalkSpec>(&self) -> bool {
        (S::SPECTRAL || !self.spectral)
            && (S::FILTER || !self.filter)
            && (S::MEDIA || !self.media)
            && (S::TEXTURES || !self.textures)
    }
}
