//! Runtime selection of the slab-test flavour: detected once when a BVH is built, kept as a
//! pair of function pointers (closest hit, occlusion), each a whole traversal compiled for
//! its instruction set.

use super::slab::Scalar;
use super::traverse::{QueryRay, SlotHit, Tree, traverse};

/// A traversal compiled for one instruction set.
pub type QueryFn = fn(Tree, &QueryRay) -> Option<SlotHit>;

/// The slab-test implementations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// Plain `[f32; 8]` arrays (what LLVM vectorises for the baseline target).
    Scalar,
    /// SSE, 4 children per instruction (x86-64 baseline).
    Sse,
    /// AVX2, 8 children per instruction.
    Avx2,
    /// NEON, 4 children per instruction (aarch64).
    Neon,
}

impl Kernel {
    pub const ALL: [Kernel; 4] = [Kernel::Scalar, Kernel::Sse, Kernel::Avx2, Kernel::Neon];

    /// The fastest flavour this CPU runs, or the one `REFRACT_BVH_KERNEL` (scalar, sse, avx2,
    /// neon) names when this CPU runs it — for measurements.
    pub fn detect() -> Kernel {
        let wanted = std::env::var("REFRACT_BVH_KERNEL").ok();
        if let Some(k) = Self::ALL
            .into_iter()
            .find(|k| Some(k.name()) == wanted.as_deref() && k.supported())
        {
            return k;
        }
        [Kernel::Avx2, Kernel::Neon, Kernel::Sse]
            .into_iter()
            .find(|k| k.supported())
            .unwrap_or(Kernel::Scalar)
    }

    pub fn name(self) -> &'static str {
        match self {
            Kernel::Scalar => "scalar",
            Kernel::Sse => "sse",
            Kernel::Avx2 => "avx2",
            Kernel::Neon => "neon",
        }
    }

    /// Whether this CPU runs the flavour.
    pub fn supported(self) -> bool {
        match self {
            Kernel::Scalar => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Sse => is_x86_feature_detected!("sse"),
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 => is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "aarch64")]
            Kernel::Neon => std::arch::is_aarch64_feature_detected!("neon"),
            #[allow(unreachable_patterns)]
            _ => false,
        }
    }

    /// Closest-hit and any-hit traversals; `None` when the CPU lacks the instruction set.
    pub fn queries(self) -> Option<(QueryFn, QueryFn)> {
        if !self.supported() {
            return None;
        }
        Some(match self {
            #[cfg(target_arch = "x86_64")]
            Kernel::Sse => (x86::sse::<false>, x86::sse::<true>),
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 => (x86::avx2::<false>, x86::avx2::<true>),
            #[cfg(target_arch = "aarch64")]
            Kernel::Neon => (arm::neon::<false>, arm::neon::<true>),
            _ => (scalar::<false>, scalar::<true>),
        })
    }
}

fn scalar<const ANY: bool>(tree: Tree, q: &QueryRay) -> Option<SlotHit> {
    traverse::<Scalar, ANY>(tree, q)
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::super::simd_x86::{Avx2, Sse};
    use super::super::traverse::{QueryRay, SlotHit, Tree, traverse};

    pub fn sse<const ANY: bool>(tree: Tree, q: &QueryRay) -> Option<SlotHit> {
        traverse::<Sse, ANY>(tree, q)
    }

    pub fn avx2<const ANY: bool>(tree: Tree, q: &QueryRay) -> Option<SlotHit> {
        // SAFETY: `Kernel::queries` hands this out only where `is_x86_feature_detected!("avx2")`
        // held on this CPU.
        unsafe { avx2_enabled::<ANY>(tree, q) }
    }

    /// The traversal with the AVX2 slab test inlined and compiled for AVX2.
    #[target_feature(enable = "avx2")]
    fn avx2_enabled<const ANY: bool>(tree: Tree, q: &QueryRay) -> Option<SlotHit> {
        traverse::<Avx2, ANY>(tree, q)
    }
}

#[cfg(target_arch = "aarch64")]
mod arm {
    use super::super::simd_neon::Neon;
    use super::super::traverse::{QueryRay, SlotHit, Tree, traverse};

    pub fn neon<const ANY: bool>(tree: Tree, q: &QueryRay) -> Option<SlotHit> {
        traverse::<Neon, ANY>(tree, q)
    }
}
