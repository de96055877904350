//! Command-line options shared by `fur render` and `fur view`: the scene (model, camera,
//! groom), how the fur is drawn, and the simulation; and the device (with `fur bench`).

use clap::Args;
use fur::render::{LightingModel, Primitive, Shading};
use fur::scene::ModelSpec;
use fur::scene::TextureSpec;
use fur::scene_file::Scene;
use fur::session::SceneOptions;
use fur::sim::SimParams;
use glam::Vec3;

/// The model, the camera, the groom and the drawing. Options left out come from the
/// scene file, if one is given, else from the model's defaults (`--model sphere` is the
/// original fur demo's scene).
#[derive(Args, Clone)]
pub struct SceneArgs {
    /// Model: `blob` (built in, the default), `sphere` (the original demo's scene: a UV
    /// sphere of radius 2, 40 × 80 bands, hairs of 12 vertices) or the path of an OBJ
    /// file.
    #[arg(long, allow_hyphen_values = true)]
    pub model: Option<ModelSpec>,
    /// Camera orbit angle around the vertical axis, degrees [default: 25; sphere: 90].
    #[arg(long, allow_negative_numbers = true)]
    pub yaw: Option<f32>,
    /// Camera elevation, degrees [default: 15].
    #[arg(long, allow_negative_numbers = true)]
    pub pitch: Option<f32>,
    /// Camera distance in bounding radii of the model [default: framing the whole model;
    /// sphere: 2.89, 10 units].
    #[arg(long, allow_negative_numbers = true)]
    pub distance: Option<f32>,
    #[command(flatten)]
    pub groom: GroomArgs,
    #[command(flatten)]
    pub draw: DrawArgs,
    #[command(flatten)]
    pub looks: LooksArgs,
}

/// Looks: texture colour, highlights, self-shadowing (`fur bench --only looks` costs
/// each).
#[derive(Args, Clone)]
pub struct LooksArgs {
    /// Colour the fur and skin from a texture through the model's UVs: a PNG, JPEG or
    /// TGA file, or `tabby` (built in, made for lat-long UVs) [default: the OBJ
    /// material's map_Kd, if any].
    #[arg(long, allow_hyphen_values = true)]
    pub texture: Option<TextureSpec>,
    /// How the hair is lit: `kajiya-kay` (the seed's model, with shifted highlights) or
    /// `marschner` (a physically based fibre model on the `[fibre]` parameters)
    /// [default: kajiya-kay].
    #[arg(long)]
    pub lighting_model: Option<LightingModel>,
    /// A second, wider highlight tinted by the hair colour, shifted toward the root
    /// (the primary shifts toward the tip): on or off [default: on].
    #[arg(long, value_parser = clap::builder::BoolishValueParser::new())]
    pub secondary_highlight: Option<bool>,
    /// Shift of the primary highlight in degrees, positive toward the tip [default: 5].
    #[arg(long, allow_negative_numbers = true)]
    pub primary_shift: Option<f32>,
    /// Shift of the secondary highlight in degrees [default: -10].
    #[arg(long, allow_negative_numbers = true)]
    pub secondary_shift: Option<f32>,
    /// Specular exponent of the secondary highlight [default: 10].
    #[arg(long, allow_negative_numbers = true)]
    pub secondary_shininess: Option<f32>,
    /// Strength of the secondary highlight [default: 0.6].
    #[arg(long, allow_negative_numbers = true)]
    pub secondary_strength: Option<f32>,
    /// Hair shadowing hair and skin, from a light-space depth map of the fur: on or off
    /// [default: off].
    #[arg(long, value_parser = clap::builder::BoolishValueParser::new())]
    pub shadows: Option<bool>,
    /// Side of the shadow map in texels, 16..=8192 [default: 512].
    #[arg(long, allow_negative_numbers = true)]
    pub shadow_resolution: Option<u32>,
    /// Light one layer of hair stops, 0..1 [default: 0.35].
    #[arg(long, allow_negative_numbers = true)]
    pub shadow_opacity: Option<f32>,
    /// Depth of one hair layer in bounding radii; 0 = the hair spacing [default: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub shadow_spacing: Option<f32>,
    /// Hairs thinner than the minimum width cover their pixels by their true width
    /// (a dithered sample mask under MSAA, blending at 1 sample): on or off [default: on].
    #[arg(long, value_parser = clap::builder::BoolishValueParser::new())]
    pub thin_hair_aa: Option<bool>,
}

/// Groom and density.
#[derive(Args, Clone)]
pub struct GroomArgs {
    /// Hair length as a fraction of the model's bounding radius [default: 0.2; sphere:
    /// 0.159, i.e. 0.55 units].
    #[arg(long, allow_negative_numbers = true)]
    pub hair_length: Option<f32>,
    /// Segments per master hair, 1..=63 [default: 16; sphere: 11].
    #[arg(long, allow_negative_numbers = true)]
    pub segments: Option<u32>,
    /// Multiplies the interpolated-hair density [default: 1; sphere: 0.33].
    #[arg(long, allow_negative_numbers = true)]
    pub density_scale: Option<f32>,
    /// Comb strength, 0 = hairs stand along the normals [default: 2; sphere: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub comb: Option<f32>,
    /// Hairs are at most this many times the model's local half-thickness long, so
    /// thin parts are not buried; 0 = off [default: 0.6; sphere: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub thickness_limit: Option<f32>,
    /// Curl radius as a fraction of the segment length [default: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub curl: Option<f32>,
}

/// How the fur is drawn: speed against image quality (`fur bench` measures each).
#[derive(Args, Clone)]
pub struct DrawArgs {
    /// Samples per pixel: 1 (no MSAA; lines then blend their coverage) or an MSAA count
    /// the device supports (lavapipe: 1 and 4) [default: 4].
    #[arg(long, allow_negative_numbers = true)]
    pub samples: Option<u32>,
    /// What each hair is drawn as: `lines` (coverage in alpha), `ribbons` (true width),
    /// or `auto`: ribbons for hairs at least --ribbon-above pixels wide at the root,
    /// lines for the rest [default: ribbons].
    #[arg(long)]
    pub primitive: Option<Primitive>,
    /// Root width in pixels from which `auto` draws ribbons [default: 1].
    #[arg(long, allow_negative_numbers = true)]
    pub ribbon_above: Option<f32>,
    /// Where Kajiya–Kay lighting runs: `vertex` (per strand vertex, geometry stage) or
    /// `fragment` [default: vertex].
    #[arg(long)]
    pub shading: Option<Shading>,
    /// Vertex LOD tolerance in pixels: a strand vertex is skipped when the segment drawn
    /// instead passes within this distance of it, width included; 0 draws every vertex
    /// [default: 0.05].
    #[arg(long, allow_negative_numbers = true)]
    pub vertex_lod: Option<f32>,
    /// Full-density distance in bounding radii: farther away the density falls with
    /// the square of the distance [default: 6].
    #[arg(long, allow_negative_numbers = true)]
    pub lod_distance: Option<f32>,
    /// Widen hairs the density LOD thins out, so coverage is kept: on or off
    /// [default: on].
    #[arg(long, value_parser = clap::builder::BoolishValueParser::new())]
    pub thickness_compensation: Option<bool>,
}

impl SceneArgs {
    /// Sets what the command line gives onto `o`.
    pub fn apply(&self, o: &mut SceneOptions) {
        let g = &self.groom;
        set(&mut o.yaw_deg, self.yaw);
        set(&mut o.pitch_deg, self.pitch);
        if self.distance.is_some() {
            o.distance = self.distance;
        }
        set(&mut o.hair_length, g.hair_length);
        set(&mut o.segments, g.segments);
        set(&mut o.density_scale, g.density_scale);
        set(&mut o.comb, g.comb);
        set(&mut o.curl, g.curl);
        set(&mut o.thickness_limit, g.thickness_limit);
        let (d, a) = (&mut o.draw, &self.draw);
        set(&mut d.samples, a.samples);
        set(&mut d.primitive, a.primitive);
        set(&mut d.ribbon_above_px, a.ribbon_above);
        set(&mut d.shading, a.shading);
        set(&mut d.vertex_lod_px, a.vertex_lod);
        set(&mut d.lod_distance, a.lod_distance);
        set(&mut d.thickness_compensation, a.thickness_compensation);
        let k = &self.looks;
        set(&mut d.thin_hair_aa, k.thin_hair_aa);
        if k.texture.is_some() {
            o.texture = k.texture.clone();
        }
        let l = &mut o.lighting;
        set(&mut l.model, k.lighting_model);
        set(&mut l.highlights.secondary, k.secondary_highlight);
        set(&mut l.highlights.primary_shift_deg, k.primary_shift);
        set(&mut l.highlights.secondary_shift_deg, k.secondary_shift);
        set(&mut l.highlights.secondary_shininess, k.secondary_shininess);
        set(&mut l.highlights.secondary_strength, k.secondary_strength);
        set(&mut l.shadows.enabled, k.shadows);
        set(&mut l.shadows.resolution, k.shadow_resolution);
        set(&mut l.shadows.opacity, k.shadow_opacity);
        set(&mut l.shadows.spacing, k.shadow_spacing);
    }

    /// Angles must be finite (distances and sizes are checked where they are used).
    pub fn check(&self) -> anyhow::Result<()> {
        for (name, v) in [("--yaw", self.yaw), ("--pitch", self.pitch)] {
            if let Some(v) = v.filter(|v| !v.is_finite()) {
                anyhow::bail!("{name} must be a finite number of degrees, got {v}");
            }
        }
        Ok(())
    }
}

/// Overwrites `field` with `value` when there is one.
pub fn set<T>(field: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *field = v;
    }
}

/// Simulation parameters (see `SimParams` for units and ranges); defaults in brackets.
#[derive(Args, Clone)]
pub struct SimArgs {
    /// Substeps per frame (1..=64) [1].
    #[arg(long, allow_negative_numbers = true)]
    pub substeps: Option<u32>,
    /// Gravity in m/s², pointing down [9.82].
    #[arg(long, allow_negative_numbers = true)]
    pub gravity: Option<f32>,
    /// Fraction of velocity lost per 1/60 s (0..1) [0.08].
    #[arg(long, allow_negative_numbers = true)]
    pub damping: Option<f32>,
    /// Global shape stiffness S_G (0..1) [0.2].
    #[arg(long, allow_negative_numbers = true)]
    pub global_stiffness: Option<f32>,
    /// Fraction of each strand the global constraint covers (0..1) [1].
    #[arg(long, allow_negative_numbers = true)]
    pub global_range: Option<f32>,
    /// Local shape stiffness S_L (0..1) [0.9].
    #[arg(long, allow_negative_numbers = true)]
    pub local_stiffness: Option<f32>,
    /// Local shape passes per substep (0..=64) [2].
    #[arg(long, allow_negative_numbers = true)]
    pub local_iterations: Option<u32>,
    /// Edge-length passes per substep (0..=64) [2].
    #[arg(long, allow_negative_numbers = true)]
    pub length_iterations: Option<u32>,
    /// Wind vector "x,y,z" in m/s², 0,0,0 = no wind [6,0,2].
    #[arg(long, value_parser = parse_vec3)]
    pub wind: Option<Vec3>,
    /// Keep the hair out of the body (a signed distance field of the model): on or off
    /// [on].
    #[arg(long, value_parser = clap::builder::BoolishValueParser::new())]
    pub collision: Option<bool>,
    /// How far outside the surface hair is kept, as a fraction of each hair's length (0..1)
    /// [0.02].
    #[arg(long, allow_negative_numbers = true)]
    pub collision_margin: Option<f32>,
    /// Fraction of a colliding vertex's sliding velocity removed per substep (0..1) [0.1].
    #[arg(long, allow_negative_numbers = true)]
    pub friction: Option<f32>,
    /// Distance-field cells along the model's longest axis (8..=128); 0 chooses from the
    /// hair length (cells about a third of it, a sixth on a skinned body, 16..=128) [0].
    #[arg(long, allow_negative_numbers = true)]
    pub sdf_resolution: Option<u32>,
    /// On a skinned body, carry the outer hair back to the rest pose's field through the
    /// skin's own blend of bones, and the hair nearest the root by the root's heaviest
    /// bone: hair stays out where the skin bends between bones and where it folds over a
    /// crease (docs/benchmark.md): on or off [on where its grid fits the device].
    #[arg(long, value_parser = clap::builder::BoolishValueParser::new())]
    pub skin_blend: Option<bool>,
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let parts: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("expected x,y,z: {e}"))?;
    match parts[..] {
        [x, y, z] => Ok(Vec3::new(x, y, z)),
        _ => Err(format!(
            "expected three comma-separated numbers, got {}",
            parts.len()
        )),
    }
}

impl SimArgs {
    /// Sets what the command line gives onto `p`.
    pub fn apply(&self, p: &mut SimParams) {
        set(&mut p.substeps, self.substeps);
        set(
            &mut p.gravity,
            self.gravity.map(|g| Vec3::new(0.0, -g, 0.0)),
        );
        set(&mut p.damping, self.damping);
        set(&mut p.global_stiffness, self.global_stiffness);
        set(&mut p.global_range, self.global_range);
        set(&mut p.local_stiffness, self.local_stiffness);
        set(&mut p.local_iterations, self.local_iterations);
        set(&mut p.length_iterations, self.length_iterations);
        set(&mut p.wind, self.wind);
        set(&mut p.collision, self.collision);
        set(&mut p.collision_margin, self.collision_margin);
        set(&mut p.friction, self.friction);
        set(&mut p.sdf_resolution, self.sdf_resolution);
        set(&mut p.skin_blend, self.skin_blend.map(Some));
    }
}

/// The scene a run draws: the model's defaults, then the scene file at `path` (if any),
/// then the command line's options.
pub fn scene(
    path: Option<&std::path::Path>,
    args: &SceneArgs,
    sim: &SimArgs,
) -> anyhow::Result<Scene> {
    let mut scene = Scene::load(path, args.model.clone())?;
    args.apply(&mut scene.options);
    sim.apply(&mut scene.sim);
    Ok(scene)
}

/// Which clip a skinned or animated model plays; options given here override the
/// scene file's `[animation]`.
#[derive(Args, Clone, Default)]
pub struct AnimationArgs {
    /// The clip to play, by name, any case (`walk` finds `Walk`); `none` holds the rest
    /// pose [default: the model's first clip].
    #[arg(long, allow_hyphen_values = true)]
    pub animation: Option<String>,
    /// Clip seconds per simulated second, 0..100 [1].
    #[arg(long, allow_negative_numbers = true)]
    pub animation_speed: Option<f32>,
    /// Clip time at the first frame, seconds [0].
    #[arg(long, allow_negative_numbers = true)]
    pub animation_start: Option<f32>,
    /// Hold the clip's last pose instead of looping.
    #[arg(long)]
    pub no_loop: bool,
    /// Keep the clip's root motion (the body walks away) instead of walking on the spot.
    #[arg(long)]
    pub root_motion: bool,
}

impl AnimationArgs {
    pub fn apply(&self, spec: &mut fur::skinning::AnimationSpec) {
        if let Some(clip) = &self.animation {
            spec.clip = Some(clip.clone());
        }
        set(&mut spec.speed, self.animation_speed);
        set(&mut spec.start, self.animation_start);
        if self.no_loop {
            spec.looping = false;
        }
        if self.root_motion {
            spec.in_place = false;
        }
    }
}

/// Which Vulkan device runs the work (`fur devices` lists them).
#[derive(Args, Clone, Default)]
pub struct DeviceArgs {
    /// The Vulkan device: its index in `fur devices`, or a case-insensitive part of its
    /// name that only one usable device has (e.g. `rtx`) [default: $FUR_DEVICE if set,
    /// else the first usable device of the best kind: discrete, integrated, virtual,
    /// cpu].
    #[arg(long, value_name = "INDEX|NAME", allow_hyphen_values = true)]
    pub device: Option<String>,
}

/// The environment variable that chooses the device when `--device` is not given.
pub const DEVICE_ENV: &str = "FUR_DEVICE";

impl DeviceArgs {
    /// The choice: `--device`, else `FUR_DEVICE` (empty counts as unset), else none.
    pub fn choice(&self) -> Option<String> {
        self.device.clone().or_else(|| {
            std::env::var(DEVICE_ENV)
                .ok()
                .filter(|v| !v.trim().is_empty())
        })
    }

    /// A headless device: the chosen one, with the validation layer if `validate`.
    pub fn headless(&self, validate: bool) -> anyhow::Result<std::sync::Arc<fur::gpu::Device>> {
        Ok(fur::gpu::headless_on(validate, self.choice().as_deref())?)
    }
}
