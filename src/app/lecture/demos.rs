//! The demonstrations of the course "Rendering: Materials", in its order: one per concept,
//! each a built-in scene, a path filter, a selection, a view and a caption that names it.

use crate::app::layer_view::ViewMode;

/// One demonstration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Demo {
    /// Name on the command line (`refract view --lecture KEY`, `refract lecture list`).
    pub key: &'static str,
    /// Button label.
    pub title: &'static str,
    /// The concept the demo teaches (its caption names it).
    pub concept: &'static str,
    /// `builtin:NAME`.
    pub scene: &'static str,
    /// The one line drawn over the image.
    pub caption: &'static str,
    /// Heckbert filter to render with ("" = every path).
    pub filter: &'static str,
    /// Inspect the paths through the pixel that sees this scene point (m), at whatever size
    /// the viewer renders.
    pub inspect: Option<[f32; 3]>,
    /// Select the material of this name (its Fresnel plot and dispersion panel show).
    pub select: Option<&'static str>,
    /// What the viewport shows (a heatmap needs the CPU backend; elsewhere: the image).
    pub view: ViewMode,
    /// A teaching switch shown in the Lecture panel while the demo is open.
    pub toggle: Option<Toggle>,
    /// A polarising filter in front of the sensor at this angle (degrees from the image's
    /// horizontal; CPU backend only, `cpu::polarized`).
    pub polarizer: Option<f32>,
}

/// A switch that breaks a law on purpose: material `material`'s albedo becomes `albedo`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Toggle {
    pub label: &'static str,
    pub material: &'static str,
    pub albedo: f32,
}

const fn demo(key: &'static str, title: &'static str, scene: &'static str) -> Demo {
    Demo {
        key,
        title,
        concept: "",
        scene,
        caption: "",
        filter: "",
        inspect: None,
        select: None,
        view: ViewMode::Beauty,
        polarizer: None,
        toggle: None,
    }
}

/// The demonstrations, in lecture order.
pub const DEMOS: [Demo; 16] = [
    Demo {
        concept: "Energy conservation",
        caption: "Energy conservation: in a white furnace (light of radiance 1 from everywhere) a \
                  white diffuse sphere, a perfect mirror and glass return exactly what they \
                  receive and vanish into the background. Break it (ρ = π: a BRDF without its \
                  1/π) and the sphere glows.",
        select: Some("white"),
        toggle: Some(Toggle {
            label: "Break it: ρ = π (a BRDF without its 1/π)",
            material: "white",
            albedo: std::f32::consts::PI,
        }),
        ..demo("energy", "Energy conservation", "builtin:furnace")
    },
    Demo {
        concept: "Three BRDF types",
        caption: "Three BRDF types: diffuse (f = ρ/π, light scattered evenly), glossy (a lobe \
                  around the mirror direction) and the perfect mirror (a Dirac delta: one \
                  direction). Click a sphere: the path inspector draws its lobe. Drag the \
                  glossy sphere's roughness to 0 and it becomes the mirror.",
        inspect: Some([-0.1284, 0.5069, 0.2853]), // on the glossy sphere, facing the camera
        select: Some("glossy"),
        ..demo("brdf-types", "Three BRDF types", "builtin:brdf-types")
    },
    Demo {
        concept: "Importance sampling",
        caption: "Importance sampling: both spheres have the same Lambert BRDF; the left one \
                  draws directions uniformly over the hemisphere (pdf 1/2π), the right one in \
                  proportion to cos θ (pdf cos θ/π). Same mean, less noise on the right.",
        select: Some("uniform"),
        ..demo("importance", "Importance sampling", "builtin:importance")
    },
    Demo {
        concept: "The perfect mirror is a Dirac delta",
        caption: "The perfect mirror is a Dirac delta: it reflects one direction only, so a \
                  shadow ray towards the light (NEE) never sees the light in it. Shown: only \
                  LSDE, the light's image thrown onto the wall — found by sampling the mirror. \
                  Clear the filter to see everything.",
        filter: "LSDE",
        select: Some("mirror"),
        ..demo("mirror", "Mirror: a Dirac delta", "builtin:mirror-delta")
    },
    Demo {
        concept: "Snell's law",
        caption: "Snell's law n₁ sin θ₁ = n₂ sin θ₂: entering the slab (n = 1.5) light bends \
                  towards the normal, leaving it bends away. Click a pixel to see its paths.",
        inspect: Some([-0.1688, 0.5048, 0.4028]), // refracts through the slab
        select: Some("glass"),
        ..demo("snell", "Snell's law", "builtin:glass-slab")
    },
    Demo {
        concept: "Fresnel reflection",
        caption: "Fresnel reflection: glass reflects 4 % of the light head-on and nearly all \
                  of it at grazing angles — the bright rim of the glass sphere.",
        select: Some("glass"),
        ..demo("fresnel", "Fresnel reflection", "builtin:env-spheres")
    },
    Demo {
        concept: "Fresnel for three indices",
        caption: "Fresnel for three indices: liquid helium (n = 1.025) reflects 0.015 % \
                  head-on and is nearly invisible, glass (1.5) 4 %, diamond (2.5) 18 % — and \
                  all of them nearly everything at grazing angles.",
        select: Some("diamond-2.5"),
        ..demo(
            "fresnel-three",
            "Helium, glass, diamond",
            "builtin:fresnel-three",
        )
    },
    Demo {
        concept: "Snell's window",
        caption: "Snell's window: from under water the whole sky is squeezed into a cone of \
                  2·asin(1/1.33) = 97.5°, and radiance entering the water is scaled by \
                  η² = 1.77 (the specular BTDF); outside the cone the surface totally reflects \
                  the sand.",
        select: Some("water"),
        ..demo("snell-window", "Snell's window", "builtin:snell-window")
    },
    Demo {
        concept: "Total internal reflection",
        caption: "Total internal reflection: beyond the critical angle asin(1/1.5) = 41.8° no \
                  light leaves the glass: the slab is a light pipe. White: every path was \
                  trapped at least once.",
        inspect: Some([0.4803, 0.3112, 0.1748]), // four TIR bounces
        select: Some("glass"),
        view: ViewMode::Tir,
        ..demo("tir", "Total internal reflection", "builtin:glass-slab")
    },
    Demo {
        concept: "Chromatic aberration",
        caption: "Chromatic aberration: the lens's index falls with wavelength, so blue \
                  focuses nearer the lens than red (1/f = (n − 1)(1/R₁ − 1/R₂)) and the spot \
                  on the screen has a coloured fringe.",
        select: Some("lens"),
        ..demo("lens", "Convex lens", "builtin:convex-lens")
    },
    Demo {
        concept: "Dispersion",
        caption: "Dispersion: the index of refraction falls with wavelength, so blue bends \
                  more than red and white light fans out into a spectrum.",
        select: Some("dispersive-glass"),
        ..demo("prism", "Prism dispersion", "builtin:prism")
    },
    Demo {
        concept: "Brewster's angle",
        caption: "Brewster's angle tan θB = n₂/n₁ (56.3° for glass): the reflected light has no \
                  component in the plane of incidence (r_p = 0, the Fresnel plot's dip), so it \
                  is polarised along the surface. The polarising filter at 90° blocks it and \
                  the panel's reflection vanishes; turn the filter towards 0° and it returns.",
        inspect: Some([0.0, 0.045, 0.0]), // the plate's centre, seen at θB
        select: Some("glass-plate"),
        polarizer: Some(90.0),
        ..demo("brewster", "Brewster's angle", "builtin:brewster")
    },
    Demo {
        concept: "Thin-film interference",
        caption: "Wave optics where it matters: thin-film interference. Light reflected at the \
                  top and at the bottom of a film a few hundred nm thick travels 2·n·d·cos θ \
                  further; wavelengths that fit a whole number of times add up, the others \
                  cancel — the bubble's bands, the oil slick, anodised metal. Drag the film \
                  thickness.",
        select: Some("soap-bubble"),
        ..demo("thin-film", "Thin-film interference", "builtin:thin-film")
    },
    Demo {
        concept: "Heckbert notation",
        caption: "Heckbert notation: only the paths LS+DE — light through one or more \
                  specular surfaces, then one diffuse bounce, then the eye: the caustic under \
                  the sphere.",
        filter: "LS+DE",
        ..demo("classes", "Path classes", "builtin:cornell-glass")
    },
    Demo {
        concept: "Caustic",
        caption: "A glass ball is a lens: it focuses the light into a bright spot on the \
                  floor — a caustic: light, two refractions, one diffuse bounce, the eye (LSSDE).",
        ..demo("caustic", "Ball-lens caustic", "builtin:caustic")
    },
    Demo {
        concept: "Caustics of a wine glass",
        caption: "Caustics of a wine glass: the bowl and the ball focus the light into bright \
                  curves and spots on the table (LS+DE), and the stem's shadow is ringed by the \
                  light it bent.",
        ..demo("wine-glass", "Wine glass", "builtin:wine-glass")
    },
];
