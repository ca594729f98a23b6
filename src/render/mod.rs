//! The render vocabulary shared by the CPU and GPU renderers and their callers (CLI, bench,
//! viewer): one options type, one estimator enum (with `auto`), one stats type, one device
//! choice, the settings sidecar that turns a loaded scene into the job that is rendered, and
//! the shards of a render split across machines (`shard`: which samples, `shard_exr`: the
//! file that records them, `shard_merge`: joining them).
//! Nothing here renders; `cpu` and `gpu` sit above it and never import each other.

pub mod device;
pub mod estimator;
pub mod estimator_plan;
pub mod options;
pub mod photon_aim;
pub mod photon_params;
pub mod photon_radius;
pub mod polarization;
pub mod race;
pub mod settings;
pub mod shard;
pub mod shard_exr;
pub mod shard_merge;
pub mod stats;

pub use device::Device;
pub use estimator::Estimator;
pub use estimator_plan::{EstimatorPlan, Runner};
pub use options::RenderOptions;
pub use polarization::Polarization;
pub use shard::Shard;
pub use stats::RenderStats;
