//! Which renderer runs: `--device` of `refract view` and `refract render`.

/// The renderer to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    /// The GPU on a hardware adapter, else the CPU (a software adapter such as lavapipe is
    /// much slower than the CPU renderer).
    #[default]
    Auto,
    /// The CPU renderer.
    Cpu,
    /// The GPU renderer on whatever adapter there is (software ones included).
    Gpu,
}

impl std::fmt::Display for Device {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Device::Auto => "auto",
            Device::Cpu => "cpu",
            Device::Gpu => "gpu",
        })
    }
}

impl std::str::FromStr for Device {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "auto" => Ok(Device::Auto),
            "cpu" => Ok(Device::Cpu),
            "gpu" => Ok(Device::Gpu),
            other => Err(format!("unknown device '{other}' (use auto, cpu or gpu)")),
        }
    }
}

impl Device {
    /// The renderers `refract bench --device` measures: `cpu`, `gpu` or `all` (both), as
    /// (cpu, gpu).
    pub fn parse_bench(s: &str) -> Result<(bool, bool), String> {
        match s.to_ascii_lowercase().as_str() {
            "cpu" => Ok((true, false)),
            "gpu" => Ok((false, true)),
            "all" => Ok((true, true)),
            d => Err(format!("unknown device '{d}' (use cpu, gpu or all)")),
        }
    }
}
