//! Command-line interface: argument parsing (clap) and the subcommands. Errors are `anyhow`
//! here, at the edge; the library reports typed errors.

mod advise;
mod bench;
mod compare;
mod merge;
mod progress;
mod render;
mod study;
mod technique;
#[cfg(feature = "viewer")]
mod view;

use std::path::PathBuf;
use std::time::Duration;

use clap::builder::TypedValueParser as _;
use clap::{Parser, Subcommand};

use pathlab::names::Named;
use pathlab::scene::Scene;

/// Exit status of a render stopped by Ctrl-C (after writing what it had).
pub const EXIT_INTERRUPTED: i32 = 130;

#[derive(Parser)]
#[command(name = "pathlab", version, about = "A GPU path tracer for studying Monte Carlo rendering")]
struct Cli {
    /// A `$name` value of a Mitsuba XML scene, overriding its `<default>` (as Mitsuba's -D);
    /// repeatable.
    #[arg(short = 'D', long = "define", global = true, value_name = "NAME=VALUE", value_parser = parse_define)]
    defines: Vec<(String, String)>,
    #[command(subcommand)]
    command: Command,
}

/// The `--define`s of this run (set once, before the command runs).
static DEFINES: std::sync::OnceLock<Vec<(String, String)>> = std::sync::OnceLock::new();

pub(crate) fn defines() -> Vec<(String, String)> {
    DEFINES.get().cloned().unwrap_or_default()
}

fn parse_define(s: &str) -> Result<(String, String), String> {
    let (name, value) = s.split_once('=').ok_or_else(|| format!("`{s}`: expected NAME=VALUE"))?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(format!("`{name}`: a name is letters, digits and _"));
    }
    Ok((name.to_string(), value.to_string()))
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene headless to an EXR file.
    Render(render::RenderArgs),
    /// Watch a scene converge in a window: switch methods live, compare two side by side at
    /// equal time, see error maps and relMSE against seconds.
    #[cfg(feature = "viewer")]
    View(view::ViewArgs),
    /// Validate a scene file and print what it contains.
    Check {
        /// Scene file (TOML, or Mitsuba 3 XML).
        scene: PathBuf,
    },
    /// Translate a Mitsuba 3 XML scene into pathlab's TOML (the same scene, the same content
    /// hash), to see what pathlab makes of it.
    Convert {
        /// Mitsuba 3 XML scene.
        scene: PathBuf,
        /// Output TOML (default: standard output).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// The variance-reduction study in one command: reference, equal-sample and equal-time
    /// tables, convergence, bias verdicts, plots, image grid and report.
    Study(study::StudyArgs),
    /// Merge partial files of a split render (render --samples / --shard) into one image,
    /// exactly: same scene, method, seed, size and depth; no overlaps, no gaps.
    Merge(merge::MergeArgs),
    /// Score one EXR against a reference: MSE, relMSE, bias, PSNR, SSIM, FLIP, z-test.
    Compare(compare::CompareArgs),
    /// Predict which method reaches a target error first, from short pilots (--verify renders
    /// the winner).
    Advise(advise::AdviseArgs),
    /// Measure samples per second of every method (device time, host overhead, compile time).
    Bench(bench::BenchArgs),
    /// Prove a sampling technique of your own (KIND:FILE.wgsl) before it renders: naga
    /// validation, then the chi-square test of its sampler against its pdf and a coverage test
    /// on configurations drawn from a scene. Exit status 0: proven; 2: refused.
    CheckTechnique(technique::CheckTechniqueArgs),
    /// List the graphics adapters wgpu can see, best first.
    Adapters,
}

/// Runs the command line and returns the process exit status.
pub fn run() -> i32 {
    let cli = Cli::parse();
    let _ = DEFINES.set(cli.defines.clone());
    let result = match cli.command {
        Command::Convert { scene, output } => convert(&scene, output.as_deref()).map(|()| 0),
        Command::Render(args) => render::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Advise(args) => advise::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Study(args) => study::run(args),
        #[cfg(feature = "viewer")]
        Command::View(args) => view::run(args),
        Command::Check { scene } => check(&scene).map(|()| 0),
        Command::CheckTechnique(args) => technique::run_check(args),
        Command::Adapters => {
            for a in pathlab::gpu::list_adapters() {
                println!("{}", pathlab::gpu::adapter_summary(&a.get_info()));
            }
            Ok(0)
        }
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            // Scene diagnostics already read `file:line:col: error: ...`.
            match e.downcast_ref::<pathlab::scene::SceneError>() {
                Some(scene_error @ pathlab::scene::SceneError::Invalid(_)) => eprintln!("{scene_error}"),
                _ => eprintln!("error: {e:#}"),
            }
            1
        }
    }
}

/// Loads a scene (with the run's `--define`s), printing its warnings to stderr.
pub(crate) fn load_scene(path: &std::path::Path) -> anyhow::Result<Scene> {
    let scene = Scene::load_with(path, &defines())?;
    for w in &scene.warnings {
        eprintln!("{w}");
    }
    Ok(scene)
}

fn convert(path: &std::path::Path, output: Option<&std::path::Path>) -> anyhow::Result<()> {
    if !pathlab::scene::is_mitsuba(path) {
        anyhow::bail!("{}: convert reads Mitsuba 3 XML scenes (.xml)", path.display());
    }
    let out_dir = match output {
        Some(o) => o.parent().map(std::path::Path::to_path_buf).unwrap_or_default(),
        None => std::env::current_dir()?,
    };
    let (text, warnings) = pathlab::scene::mitsuba::to_toml(path, &defines(), &out_dir)?;
    for w in &warnings {
        eprintln!("{w}");
    }
    match output {
        Some(o) => {
            pathlab::output::write_atomically(o, |w| std::io::Write::write_all(w, text.as_bytes()).map_err(|e| e.to_string()))?;
            eprintln!("wrote {}", o.display());
        }
        None => print!("{text}"),
    }
    Ok(())
}

fn check(path: &std::path::Path) -> anyhow::Result<()> {
    let scene = load_scene(path)?;
    let f = pathlab::gpu::SceneFeatures::of(&scene);
    println!(
        "{}: valid; {}x{}, max_depth {}, Russian roulette {}, {} materials, {} spheres ({} lights), {} planes ({} can shadow a light), \
         {} meshes ({} triangles, {} emissive{}), {}specular {}, BSDFs {}, environment {}, light interiors reachable {}; \
         default light selection {}; scene hash {}",
        path.display(),
        scene.render.width,
        scene.render.height,
        scene.render.max_depth,
        scene.render.rr_depth.map_or("off".to_string(), |k| format!("from vertex {k}")),
        scene.materials.len(),
        f.num_spheres,
        f.num_sphere_lights,
        f.num_planes,
        f.num_occluding_planes,
        scene.meshes.len(),
        f.num_triangles,
        f.num_triangle_lights,
        if scene.meshes.iter().any(|m| !m.normals.is_empty()) { ", with vertex normals" } else { "" },
        if f.num_disks + f.num_cylinders + f.num_curve_segments + f.num_bspline_segments + f.num_sdf_grids > 0 {
            let mut curves = if f.num_curve_segments > 0 { format!("{} curve segments, ", f.num_curve_segments) } else { String::new() };
            if f.num_bspline_segments > 0 {
                curves += &format!("{} B-spline segments, ", f.num_bspline_segments);
            }
            let grids = scene
                .quadrics
                .iter()
                .filter_map(|q| q.grid())
                .map(|g| format!("{}x{}x{} ({} normals), ", g.res[0], g.res[1], g.res[2], if g.smooth { "smooth" } else { "analytic" }))
                .collect::<Vec<_>>();
            let grids = if grids.is_empty() { String::new() } else { format!("{} signed distance grids: {}", grids.len(), grids.concat()) };
            format!("{} disks ({} lights), {} cylinders, {curves}{grids}", f.num_disks, f.num_disk_lights, f.num_cylinders)
        } else {
            String::new()
        },
        if f.has_specular { "yes" } else { "no" },
        pathlab::scene::BsdfKind::ALL
            .iter()
            .map(|&k| (k, scene.materials.iter().filter(|m| m.bsdf_kind() == k).count()))
            .filter(|&(_, n)| n > 0)
            .map(|(k, n)| format!("{k} x{n}"))
            .collect::<Vec<_>>()
            .join(", "),
        if f.has_environment { "yes" } else { "no" },
        if f.light_interiors_reachable { "yes" } else { "no" },
        scene.default_light_select(),
        scene.content_hash(),
    );
    if scene.render.hide_emitters {
        println!(
            "hide_emitters: camera rays pass through up to {} area emitter surfaces and see no environment (Mitsuba's hide_emitters)",
            f.emitter_skips()
        );
    }
    // A scene's [techniques]: valid WGSL fitting the contract (naga, no GPU); their check
    // needs one (`pathlab check-technique`).
    for t in &scene.techniques {
        pathlab::shaders::validate_technique(t)?;
        println!("technique {}: {} ({} loops guarded), sha256 {}; use it as +{}={}", t.label(), t.path.display(), t.loops, t.sha256, t.kind, t.name);
    }
    let textures: Vec<(&str, &pathlab::scene::Texture)> =
        scene.materials.iter().flat_map(|m| m.textures().into_iter().map(move |t| (m.name.as_str(), t))).collect();
    if !textures.is_empty() {
        let bytes: u64 = textures.iter().map(|(_, t)| t.gpu_bytes()).sum();
        println!("textures: {}, GPU memory {:.2} MiB (BSDF data)", textures.len(), bytes as f64 / (1 << 20) as f64);
        for (material, t) in &textures {
            println!("  {material}: {} ({:.1} KiB)", t.describe(), t.gpu_bytes() as f64 / 1024.0);
        }
    }
    let masked: Vec<String> = scene
        .materials
        .iter()
        .filter_map(|m| {
            m.opacity.as_ref().map(|o| match o {
                pathlab::scene::Opacity::Constant(c) => format!("{} (opacity {})", m.name, *c as f32),
                pathlab::scene::Opacity::Texture(t) => format!("{} (opacity a {})", m.name, texture_and_mean(t, o.mean())),
            })
        })
        .collect();
    if !masked.is_empty() {
        // Under volpath (a scene with media) shadow rays see through a mask by its opacity, as
        // Mitsuba's volpath does; under path they do not, as Mitsuba's path.
        let shadows = if scene.media.is_empty() { "shadow rays do not see through" } else { "shadow rays see through by 1 - opacity, as in Mitsuba's volpath" };
        println!("masks: {} material(s) let rays through (Mitsuba's mask; {shadows}): {}", masked.len(), masked.join(", "));
    }
    let mapped: Vec<&str> = scene.materials.iter().filter(|m| m.normal_map.is_some()).map(|m| m.name.as_str()).collect();
    if !mapped.is_empty() {
        println!("normal maps: {} material(s) scatter in a normal map's perturbed frame (Mitsuba's normalmap): {}", mapped.len(), mapped.join(", "));
    }
    let bumped: Vec<String> = scene.materials.iter().filter_map(|m| m.bump_map.as_ref().map(|b| format!("{} (scale {})", m.name, b.scale as f32))).collect();
    if !bumped.is_empty() {
        println!("bump maps: {} material(s) scatter in the frame of a bumped surface (Mitsuba's bumpmap): {}", bumped.len(), bumped.join(", "));
    }
    let anisotropic: Vec<&str> = scene.materials.iter().filter(|m| m.bsdf.is_anisotropic()).map(|m| m.name.as_str()).collect();
    if !anisotropic.is_empty() {
        println!("anisotropic roughness: {} material(s), placed by each shape's dp/du: {}", anisotropic.len(), anisotropic.join(", "));
    }
    let backs: Vec<String> = scene.materials.iter().filter_map(|m| m.back.map(|b| format!("{} (back: {})", m.name, scene.materials[b].name))).collect();
    if !backs.is_empty() {
        println!("two BSDFs: {} material(s) scatter by another BSDF on their back (Mitsuba's twosided with two): {}", backs.len(), backs.join(", "));
    }
    let blends: Vec<String> = scene
        .materials
        .iter()
        .filter_map(|m| {
            m.blend.as_ref().map(|b| match &b.weight {
                pathlab::scene::Opacity::Constant(w) => format!("{} (with {}, weight {})", m.name, scene.materials[b.material].name, *w as f32),
                pathlab::scene::Opacity::Texture(t) => format!("{} (with {}, weight a {})", m.name, scene.materials[b.material].name, texture_and_mean(t, b.weight.mean())),
            })
        })
        .collect();
    if !blends.is_empty() {
        println!("blends: {} material(s) blend another BSDF by a weight, one of the two picked per path vertex (Mitsuba's blendbsdf): {}", blends.len(), blends.join(", "));
    }
    let textured_lights: Vec<String> = scene
        .materials
        .iter()
        .filter_map(|m| m.emission_texture.as_ref().map(|t| format!("{} (a {}, mean {:?})", m.name, t.name(), m.emission.as_vec3().to_array())))
        .collect();
    if !textured_lights.is_empty() {
        println!(
            "emission textures: {} material(s) emit a texture over their uv parametrisation (Mitsuba's area emitter with a textured radiance; lights are picked by its mean): {}",
            textured_lights.len(),
            textured_lights.join(", ")
        );
    }
    if let pathlab::scene::Projection::Orthographic { width } = scene.camera.projection {
        let (_, half_height) = scene.camera.projection.half_extents(scene.render.width, scene.render.height);
        println!("camera: orthographic, parallel rays from a {} x {} rectangle (scene units)", width, 2.0 * half_height);
    }
    if scene.camera.aperture_radius > 0.0 {
        println!(
            "camera: thin lens, aperture radius {}, in focus at distance {} (depth of field; the lens takes sample dimensions 2 and 3)",
            scene.camera.aperture_radius, scene.camera.focus_distance
        );
    }
    // Participating media: what each is, which materials bound it, whether the camera is in it.
    for (i, m) in scene.media.iter().enumerate() {
        let phase = match m.phase {
            pathlab::scene::media::Phase::Isotropic => "isotropic".to_string(),
            pathlab::scene::media::Phase::HenyeyGreenstein { g } => format!("Henyey-Greenstein g {g}"),
        };
        let bounds: Vec<&str> = scene.materials.iter().filter(|t| t.interior == Some(i) || t.exterior == Some(i)).map(|t| t.name.as_str()).collect();
        println!(
            "medium {i} \"{}\": {}, {phase}; bounded by {}{}",
            m.name,
            m.describe(),
            if bounds.is_empty() { "no material".to_string() } else { bounds.join(", ") },
            if scene.camera_medium == Some(i) { "; the camera is in it" } else { "" }
        );
    }
    if !scene.media.is_empty() {
        println!("media: {}; rendered by the volumetric path tracer (Mitsuba's volpath in expectation)", scene.media.len());
    }
    // Delta lights: what they are, and that only next event estimation sees them.
    for (i, l) in scene.point_lights.iter().enumerate() {
        println!("point light {i}: at {:?}, intensity {:?} W/sr", l.position.to_array(), l.intensity.to_array());
    }
    for (i, l) in scene.spot_lights.iter().enumerate() {
        println!(
            "spot light {i}: at {:?} along {:?}, intensity {:?} W/sr, cutoff {} deg, beam width {} deg{}",
            l.position.to_array(),
            l.direction.to_array(),
            l.intensity.to_array(),
            l.cutoff_angle,
            l.beam_width,
            l.texture.as_ref().map_or(String::new(), |t| format!(", projecting {} (up {:?})", t.texture.describe(), t.up.to_array()))
        );
    }
    for (i, l) in scene.directional_lights.iter().enumerate() {
        println!("directional light {i}: along {:?}, irradiance {:?}", l.direction.to_array(), l.irradiance.to_array());
    }
    for (i, l) in scene.projector_lights.iter().enumerate() {
        let (w, h) = l.resolution();
        let (fx, fy) = l.fov.angles(w, h);
        println!(
            "projector {i}: at {:?} along {:?}, up {:?}, field of view {fx:.3} x {fy:.3} deg, irradiance {}, scale {}",
            l.position.to_array(),
            l.direction.to_array(),
            l.up.to_array(),
            l.irradiance.describe(),
            l.scale
        );
    }
    if scene.num_delta_lights() > 0 {
        println!("delta lights: {}; only methods with next event estimation see them (not lights=none)", scene.num_delta_lights());
    }
    if let Some(c) = scene.translation.sensor_correction {
        println!("sensor to_world: orthonormalised, its axes moved by at most {c:.2e} rad ({:.2e} degrees)", c.to_degrees());
    }
    if let Some(i) = scene.translation.instancing {
        println!(
            "instances: {} of {} shape group(s), flattened into {} world-space shapes (in the counts above)",
            i.instances, i.groups, i.shapes
        );
    }
    if let Some(m) = &scene.environment_map {
        let name = m.file.file_name().map_or_else(|| m.file.display().to_string(), |n| n.to_string_lossy().into_owned());
        println!(
            "environment map: {name} {}x{}, scale {}, mean radiance (luminance) {:.4}, GPU memory {:.2} MiB (texels and the luminance and compensated distributions){}",
            m.image.width,
            m.image.height,
            m.scale,
            m.mean_luminance(),
            (m.pack().len() * 4) as f64 / (1 << 20) as f64,
            if m.is_black() { "; black: not a light" } else { "" }
        );
    }
    if f.num_triangles > 0 {
        let start = std::time::Instant::now();
        let packed = pathlab::gpu::PackedTriangles::new(&scene, false);
        let built = start.elapsed();
        let b = &packed.bvh;
        println!(
            "BVH: {} triangles, {} nodes ({} leaves), depth {}, built in {:.1} ms (with the light table); \
             GPU memory {:.2} MiB (triangles {:.2}, normals {:.2}, nodes {:.2})",
            packed.triangles.len(),
            b.nodes.len(),
            b.nodes.iter().filter(|n| n.count > 0).count(),
            b.depth,
            built.as_secs_f64() * 1e3,
            packed.gpu_bytes() as f64 / (1 << 20) as f64,
            (packed.triangles.len() * 48) as f64 / (1 << 20) as f64,
            (packed.normals.len() * 48) as f64 / (1 << 20) as f64,
            (b.nodes.len() * std::mem::size_of::<pathlab::accel::BvhRecord>()) as f64 / (1 << 20) as f64,
        );
        let names = scene.mesh_attribute_names();
        if !names.is_empty() {
            // Which meshes carry each attribute a texture reads, and the table's size.
            let carried: Vec<String> = names
                .iter()
                .map(|n| format!("{n} on {} of {} meshes", scene.meshes.iter().filter(|m| m.attribute(n).is_some()).count(), scene.meshes.len()))
                .collect();
            println!(
                "mesh attributes read by textures: {}; GPU memory {:.2} MiB (each triangle's corners)",
                carried.join(", "),
                std::mem::size_of_val(&packed.attributes[..]) as f64 / (1 << 20) as f64
            );
        }
        if let Some((shared, _)) = packed.shared_vertices() {
            let hull = packed.triangles.len() as u32 - scene.shadow_tests_of(&packed.corners()).count_ones().min(packed.triangles.len() as u32);
            let mut skipped = if hull > 0 {
                format!("; shadow rays to lights skip the {hull} they cannot meet first: faces of the scene's hull, and of closed convex meshes turned away from every light (unless next event estimation samples the environment)")
            } else {
                String::new()
            };
            let pairs = scene.front_face_pairs(&packed.corners(), &packed.materials()).len();
            if pairs > 0 {
                skipped += &format!("; other rays test one face of each of {pairs} pairs of opposite faces of closed convex meshes, the one turned towards them");
            }
            println!(
                "Small scene: on a CPU adapter the kernel tests all {} triangles in turn (at most {}), on {} distinct vertices sheared once per ray ({} corners){skipped}",
                packed.triangles.len(),
                pathlab::accel::BRUTE_FORCE_TRIANGLES,
                shared.count,
                3 * packed.triangles.len(),
            );
        }
    }
    Ok(())
}

/// The parser of a `Named` choice: its names as clap's possible values (each with its
/// description in `--help`), parsed into the value.
pub(crate) fn named<T: Named + Clone + Send + Sync>() -> impl clap::builder::TypedValueParser<Value = T> {
    let values = T::all().iter().map(|v| {
        let help = v.description().split_whitespace().collect::<Vec<_>>().join(" ");
        clap::builder::PossibleValue::new(v.name()).help(help)
    });
    clap::builder::PossibleValuesParser::new(values).map(|s| T::from_name(&s).expect("a possible value"))
}

/// Parses a method name: a preset, a named variant or biased demonstration, or parts
/// `SAMPLER/BSDF/LIGHTS`, each with `+OPTION`s (`Method::from_name`, as Python and every command).
pub(crate) fn parse_method(s: &str) -> Result<pathlab::method::Method, String> {
    pathlab::method::Method::from_name(s.trim()).map_err(|e| e.to_string())
}

/// Parses an image size `WxH`.
pub(crate) fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("expected WxH, got {s}"))?;
    let parse = |v: &str| v.trim().parse::<u32>().ok().filter(|&n| n > 0).ok_or_else(|| format!("bad size {s}"));
    Ok((parse(w)?, parse(h)?))
}

/// Parses a duration: seconds (`90`, `0.5`) or with a unit (`30s`, `5m`, `2h`).
pub(crate) fn parse_duration(s: &str) -> Result<Duration, String> {
    let t = s.trim();
    let (number, scale) = match t.chars().last() {
        Some('s') => (&t[..t.len() - 1], 1.0),
        Some('m') => (&t[..t.len() - 1], 60.0),
        Some('h') => (&t[..t.len() - 1], 3600.0),
        _ => (t, 1.0),
    };
    let v: f64 = number.trim().parse().map_err(|_| format!("`{s}` is not a duration (e.g. 90, 30s, 5m, 2h)"))?;
    if !(v.is_finite() && v > 0.0) {
        return Err(format!("`{s}`: the duration must be positive"));
    }
    Ok(Duration::from_secs_f64(v * scale))
}

/// `--rr-depth K|off`: Russian roulette from scattering vertex K >= 1 on, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct RrDepth(pub Option<u32>);

impl std::str::FromStr for RrDepth {
    type Err = String;
    fn from_str(s: &str) -> Result<RrDepth, String> {
        if s.trim() == "off" {
            return Ok(RrDepth(None));
        }
        match s.trim().parse::<u32>() {
            Ok(k) if k >= 1 => Ok(RrDepth(Some(k))),
            _ => Err(format!("`{s}`: expected a depth >= 1 (the first scattering vertex is 1) or `off`")),
        }
    }
}

/// A refused override, named by its flag (`max_depth` is `--max-depth`).
pub(crate) fn flag_error(e: pathlab::scene::OverrideError) -> anyhow::Error {
    anyhow::anyhow!("--{} must be {}", e.field.replace('_', "-"), e.requirement)
}

/// Size, depth and display-transform overrides of the scene, shared by `study` and `advise`.
#[derive(clap::Args)]
pub(crate) struct SceneOverrides {
    /// Image size WxH (default: the scene's).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Path segments (default: the scene's).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Russian roulette from this scattering vertex on (the first is 1), or `off` (default:
    /// the scene's render.rr_depth, else off).
    #[arg(long)]
    pub rr_depth: Option<RrDepth>,
    /// Display transform of PSNR, SSIM, FLIP and figures: `srgb` or `gamma:G` (default: the
    /// scene's [display] table, else srgb).
    #[arg(long)]
    pub display: Option<pathlab::display::Transfer>,
}

impl SceneOverrides {
    /// Applies size (else `fallback_size`) and depth to `scene`; returns the display transform.
    pub fn apply(&self, scene: &mut Scene, fallback_size: Option<(u32, u32)>) -> anyhow::Result<pathlab::display::DisplayTransform> {
        let size = self.size.or(fallback_size);
        let overrides = pathlab::scene::Overrides {
            width: size.map(|s| s.0),
            height: size.map(|s| s.1),
            max_depth: self.max_depth,
            rr_depth: self.rr_depth.map(|RrDepth(rr)| rr),
            spp: None,
        };
        if let Some(reframing) = overrides.apply(scene).map_err(flag_error)? {
            eprintln!("note: {reframing}");
        }
        Ok(match self.display {
            Some(transfer) => pathlab::display::DisplayTransform { transfer, ..scene.display },
            None => scene.display,
        })
    }
}

/// A weight's texture for `check`: its kind and mean, or for a mesh attribute, whose mean the host
/// does not know, its name.
fn texture_and_mean(t: &pathlab::scene::Texture, mean: f64) -> String {
    match t.mesh_attribute() {
        Some(name) => format!("{} \"{name}\"", t.name()),
        None => format!("{}, mean {mean:.3}", t.name()),
    }
}
