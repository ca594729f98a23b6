//! `refract view` (and no subcommand): the interactive viewer.

use super::ViewArgs;
use anyhow::{Result, bail};
use refract::math::spectrum;

pub(super) fn view(args: ViewArgs) -> Result<()> {
    let inspect = match args.inspect.as_deref() {
        None => None,
        Some(&[x, y]) => Some((x, y)),
        Some(_) => bail!("--inspect takes two numbers, X and Y"),
    };
    let env = &args.env;
    let env = (env.env.is_some() || env.env_strength.is_some() || env.env_rotation.is_some()).then(
        || refract::app::EnvOverride {
            file: env.env.clone(),
            strength: env.env_strength,
            rotation: env.env_rotation,
        },
    );
    if let Some(nm) = args.light_line {
        spectrum::check_light_line(nm, "--light-line").map_err(anyhow::Error::msg)?;
    }
    let lecture = args
        .lecture
        .as_deref()
        .map(refract::app::lecture::find)
        .transpose()?;
    refract::app::run(refract::app::ViewOptions {
        inspect,
        env,
        scene: lecture.map(|d| d.scene.to_owned()).or(args.scene),
        lecture: lecture.map(|d| d.key),
        frames: args.frames,
        exit_after: args.exit_after,
        device: args.device,
        limits: args.load.limits(),
        view: args.view,
        light_line: args.light_line,
        window_renderer: args.window_renderer,
    })
}
