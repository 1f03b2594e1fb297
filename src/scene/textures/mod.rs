//! Textures: spatially varying parameters of BSDFs, looked up at a hit's uv parametrisation
//! (Mitsuba 3's `src/textures/`). One mechanism for every kind: a colour slot of a BSDF's
//! parameter block holds either its value or a reference to a texture in the BSDF data
//! (`texture_slot` in shaders/texture.wgsl), and the slots that may be textures are the kind's
//! `BsdfPlugin::TEXTURE_SLOTS`, resolved before the BSDF is evaluated (the generated
//! `bsdf_apply_textures`), so that no BSDF's code knows of textures. Scenes without textures
//! compile all texture code out (the pipeline constant `HAS_UVS`), and a scene compiles the
//! lookups of the kinds it uses alone (`TEXTURE_KINDS`).
//!
//! Kinds: Mitsuba's `checkerboard` (`color0`, default 0.4; `color1`, default 0.2; `to_uv`, a
//! 2D affine map, `to_uv_scale` where it only scales), `bitmap` (an image file; `bitmap.rs`) and `volume` (a `.vol` grid looked up at the
//! hit's world position rather than its uvs; `volume.rs`). TOML: a colour field given as an
//! inline table,
//! `diffuse = { texture = "checkerboard", color0 = [0.8, 0.8, 0.8], color1 = 0.2, to_uv_scale = [20, 80] }`,
//! `diffuse = { texture = "bitmap", filename = "wood.png", filter_type = "bilinear", wrap_mode = "repeat", raw = false, to_uv = [[2, 0, 0], [0, 2, 0]] }`,
//! `diffuse = { texture = "volume", filename = "marble.vol", filter_type = "trilinear", wrap_mode = "clamp", to_world = [[2, 0, 0, -1], [0, 2, 0, 0], [0, 0, 2, -1]] }`
//! (the file relative to the scene's folder; the defaults as shown but `to_uv`, the identity),
//! `diffuse = { texture = "rawconstant", value = [x, y, z] }`, and
//! `diffuse = { texture = "mesh_attribute", name = "vertex_color", scale = 1.0 }` (a PLY mesh's
//! named attribute at the hit, `mesh::MeshAttribute`).

pub mod bitmap;
pub mod volume;

use std::ops::Range;
use std::path::Path;

pub use bitmap::{Bitmap, Filter, Wrap};
pub use volume::GridVolume;

use glam::{DVec2, DVec3};

use crate::scene::bsdf_data::BsdfData;
use crate::scene::raw::RawColor;

/// Mitsuba's checkerboard colours by default.
const DEFAULT_COLOR0: f64 = 0.4;
const DEFAULT_COLOR1: f64 = 0.2;

/// The kinds' numbers in the BSDF data (`TEXTURE_*` in texture.wgsl).
pub const TEXTURE_CHECKERBOARD: u32 = 0;
/// Mitsuba's `rawconstant` (bitmap 1, volume 2 in their files).
pub const TEXTURE_RAW_CONSTANT: u32 = 3;
/// Mitsuba's `mesh_attribute`: a named attribute of the mesh that was hit.
pub const TEXTURE_MESH_ATTRIBUTE: u32 = 5;
/// A checkerboard whose `to_uv` does more than scale: its own kind, so that scenes of scaled
/// checkerboards (all before 2026-12-05) keep their two-number record and their speed.
pub const TEXTURE_CHECKERBOARD_AFFINE: u32 = 4;

/// A texture and its parameters.
#[derive(Debug, Clone, PartialEq)]
pub enum Texture {
    /// Mitsuba's `checkerboard`: `color0` where the fractional parts of u and v (after
    /// `to_uv`, rows of a 2D affine map as a bitmap's: uv' = (m00 u + m01 v + m02, m10 u +
    /// m11 v + m12)) are both above 1/2 or both not, `color1` elsewhere.
    Checkerboard { color0: DVec3, color1: DVec3, to_uv: [[f64; 3]; 2] },
    /// Mitsuba's `bitmap`: an image file.
    Bitmap(Bitmap),
    /// Mitsuba's `volume` around a `gridvolume`: a 3D grid looked up at the hit's world
    /// position (`volume.rs`).
    Volume(GridVolume),
    /// Mitsuba's `rawconstant` (src/spectra/rawconstant.cpp): one value everywhere, taken as
    /// given, without colour conversion or range checks (a normal map's constant normal, say);
    /// one number stands for three equal ones.
    RawConstant { value: DVec3 },
    /// Mitsuba's `mesh_attribute` (src/textures/mesh_attribute.cpp): the attribute `name`
    /// (`vertex_color`, `face_weight`: `mesh::MeshAttribute`) of the mesh that was hit, times
    /// `scale`: a vertex attribute interpolated by the hit's barycentrics, a face attribute the
    /// face's row. One channel reads as grey. `scalar`: read as Mitsuba's `eval_1` (a weight,
    /// an opacity), which needs a one-channel attribute (Mitsuba's gives 0 for three).
    /// Validation checks that every mesh whose material reads it has it (`check_meshes`).
    MeshAttribute { name: String, scale: f64, scalar: bool },
}

impl Texture {
    /// Its name in TOML and Mitsuba (`checkerboard`).
    pub fn name(&self) -> &'static str {
        match self {
            Texture::Checkerboard { .. } => "checkerboard",
            Texture::Bitmap(_) => "bitmap",
            Texture::Volume(_) => "volume",
            Texture::RawConstant { .. } => "rawconstant",
            Texture::MeshAttribute { .. } => "mesh_attribute",
        }
    }

    /// Its kind's number in the BSDF data (`TEXTURE_CHECKERBOARD`, `TEXTURE_BITMAP`,
    /// `TEXTURE_VOLUME`): the bit it sets in the kernel's `TEXTURE_KINDS`.
    pub fn kind_number(&self) -> u32 {
        match self {
            Texture::Checkerboard { to_uv, .. } if scale_of(to_uv).is_none() => TEXTURE_CHECKERBOARD_AFFINE,
            Texture::Checkerboard { .. } => TEXTURE_CHECKERBOARD,
            Texture::Bitmap(_) => bitmap::TEXTURE_BITMAP,
            Texture::Volume(_) => volume::TEXTURE_VOLUME,
            Texture::RawConstant { .. } => TEXTURE_RAW_CONSTANT,
            Texture::MeshAttribute { .. } => TEXTURE_MESH_ATTRIBUTE,
        }
    }

    /// Its mean over the uv square (Mitsuba's `mean()`): what a host computation that needs one
    /// value (a lobe's sampling weight) takes.
    pub fn mean(&self) -> DVec3 {
        match self {
            Texture::Checkerboard { color0, color1, .. } => 0.5 * (*color0 + *color1),
            Texture::Bitmap(b) => DVec3::from(b.image.mean()),
            Texture::Volume(v) => DVec3::from(v.mean()),
            Texture::RawConstant { value } => *value,
            // A stand-in: the host does not know it (nor does Mitsuba, whose mesh_attribute has
            // no mean()). Host computations read a textured slot's mean only as a sampling
            // weight (a lobe's, a light's by power), for which any positive value is unbiased.
            Texture::MeshAttribute { scale, .. } => DVec3::splat(scale.abs()),
        }
    }

    /// Mitsuba's `mean()` of it, one number (what its plastics' `specular_sampling_weight`
    /// reads): a checkerboard's is the mean of its colours' channel means, a bitmap's the mean
    /// luminance of its texels.
    pub fn mitsuba_mean(&self) -> f64 {
        match self {
            Texture::Checkerboard { color0, color1, .. } => 0.5 * (color0.element_sum() + color1.element_sum()) / 3.0,
            Texture::Bitmap(b) => crate::scene::emitters::luminance(DVec3::from(b.image.mean())),
            Texture::Volume(v) => crate::scene::emitters::luminance(DVec3::from(v.mean())),
            // Mitsuba's dr::mean of the value.
            Texture::RawConstant { value } => value.element_sum() / 3.0,
            Texture::MeshAttribute { scale, .. } => scale.abs(),
        }
    }

    /// The texture as Mitsuba's `eval_1` reads it (a scalar parameter: an opacity, a roughness),
    /// for a kernel that takes the luminance of every texture's value (`texture_value_1` in
    /// texture.wgsl): a bitmap unchanged (its luminance is Mitsuba's), a checkerboard with its
    /// colours replaced by their channel means (grey) and swapped, as Mitsuba 3.9.1's
    /// `Checkerboard::eval_1` gives `color0` where its `eval` gives `color1` (its test is
    /// `mask.x() != mask.y()` where `eval`'s is `==`), which the z-test against Mitsuba's own
    /// render of a masked checkerboard confirms (tests/masks.rs).
    pub fn scalar(self) -> Texture {
        match self {
            Texture::Checkerboard { color0, color1, to_uv } => Texture::Checkerboard {
                color0: DVec3::splat(color1.element_sum() / 3.0),
                color1: DVec3::splat(color0.element_sum() / 3.0),
                to_uv,
            },
            Texture::MeshAttribute { name, scale, .. } => Texture::MeshAttribute { name, scale, scalar: true },
            t => t,
        }
    }

    /// Its scalar value at `uv` and world position `p` (a texture made by `scalar`): the
    /// luminance of its value, in f32 as the kernel's `texture_value_1`.
    pub fn eval_1(&self, uv: [f32; 2], p: [f32; 3]) -> f32 {
        luminance_f32(self.eval(uv, p))
    }

    /// Its value at `uv` (surface textures) or world position `p` (a volume), in f32 as the
    /// kernel computes it: the host's twin of `eval_texture`.
    pub fn eval(&self, uv: [f32; 2], p: [f32; 3]) -> [f32; 3] {
        match self {
            Texture::Checkerboard { color0, color1, to_uv } => {
                // As the kernel: u su for a scale, else m00 u + m01 v + m02, in that order.
                let m = to_uv.map(|r| r.map(|x| x as f32));
                let (u, v) = match scale_of(to_uv) {
                    Some(_) => (uv[0] * m[0][0], uv[1] * m[1][1]),
                    None => (m[0][0] * uv[0] + m[0][1] * uv[1] + m[0][2], m[1][0] * uv[0] + m[1][1] * uv[1] + m[1][2]),
                };
                let (mu, mv) = (u - u.floor() > 0.5, v - v.floor() > 0.5);
                if mu == mv { color0.as_vec3().to_array() } else { color1.as_vec3().to_array() }
            }
            Texture::Bitmap(b) => b.eval(uv),
            Texture::Volume(v) => v.eval(p),
            Texture::RawConstant { value } => value.as_vec3().to_array(),
            // Its value depends on the mesh hit, which a uv and a point do not name: the host
            // twin gives its stand-in mean (`mean`).
            Texture::MeshAttribute { .. } => self.mean().as_vec3().to_array(),
        }
    }

    /// Its record in the BSDF data: the kind, then its parameters; returns where it starts.
    pub fn pack(&self, data: &mut BsdfData) -> u32 {
        match self {
            Texture::Checkerboard { color0, color1, to_uv } => {
                let (c0, c1) = (color0.as_vec3(), color1.as_vec3());
                let m = to_uv.map(|r| r.map(|x| x as f32));
                match scale_of(to_uv) {
                    Some(_) => data.push(&[TEXTURE_CHECKERBOARD as f32, c0.x, c0.y, c0.z, c1.x, c1.y, c1.z, m[0][0], m[1][1]]),
                    None => data.push(&[TEXTURE_CHECKERBOARD_AFFINE as f32, c0.x, c0.y, c0.z, c1.x, c1.y, c1.z, m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2]]),
                }
            }
            Texture::Bitmap(b) => b.pack(data),
            Texture::Volume(v) => v.pack(data),
            Texture::RawConstant { value } => {
                let v = value.as_vec3();
                data.push(&[TEXTURE_RAW_CONSTANT as f32, v.x, v.y, v.z])
            }
            // The attribute's slot among the scene's (`Scene::mesh_attribute_names`, the order
            // of the kernel's attribute table), the scale, the number of slots.
            Texture::MeshAttribute { name, scale, .. } => {
                let slot = data.attribute_slot(name);
                data.push(&[TEXTURE_MESH_ATTRIBUTE as f32, slot as f32, *scale as f32, data.1.len() as f32])
            }
        }
    }

    /// One line for `pathlab check`: its kind and parameters, for a bitmap its image.
    pub fn describe(&self) -> String {
        match self {
            Texture::Checkerboard { to_uv, .. } => match scale_of(to_uv) {
                Some(s) => format!("checkerboard, to_uv scale ({}, {})", s[0], s[1]),
                None => format!("checkerboard, to_uv {:?}", to_uv),
            },
            Texture::Bitmap(b) => {
                let storage = match (&b.image.texels, b.image.srgb) {
                    (crate::scene::image_file::Texels::Bytes(_), true) => "8-bit sRGB",
                    (crate::scene::image_file::Texels::Bytes(_), false) => "8-bit linear",
                    (crate::scene::image_file::Texels::Float(_), _) => "float",
                };
                let name = b.file.file_name().map_or_else(|| b.file.display().to_string(), |n| n.to_string_lossy().into_owned());
                format!("bitmap {name} {}x{} {storage}, {}, {}", b.image.width, b.image.height, b.filter.name(), b.wrap.name())
            }
            Texture::Volume(v) => {
                let name = v.file.file_name().map_or_else(|| v.file.display().to_string(), |n| n.to_string_lossy().into_owned());
                let colour = if v.channels == 1 { "grey" } else { "RGB" };
                format!("volume {name} {}x{}x{} {colour}, {}, {}", v.res[0], v.res[1], v.res[2], if v.trilinear { "trilinear" } else { "nearest" }, v.wrap.name())
            }
            Texture::RawConstant { value } => format!("rawconstant ({}, {}, {})", value.x, value.y, value.z),
            Texture::MeshAttribute { name, scale, .. } => format!("mesh_attribute {name}, scale {scale}"),
        }
    }

    /// Bytes of its record on the GPU (what `pathlab check` reports as its memory).
    pub fn gpu_bytes(&self) -> u64 {
        4 * match self {
            Texture::Checkerboard { to_uv, .. } => if scale_of(to_uv).is_some() { 9 } else { 13 },
            Texture::Bitmap(b) => b.record_len(),
            Texture::Volume(v) => v.record_len(),
            Texture::RawConstant { .. } => 4,
            // The record; the attribute's table counts with the triangles.
            Texture::MeshAttribute { .. } => 4,
        }
    }

    /// Its line of the scene hash, its vectors written by `vec3` (the hash's own format).
    pub fn hash_value(&self, vec3: impl Fn(DVec3) -> String) -> String {
        match self {
            Texture::Checkerboard { color0, color1, to_uv } => match scale_of(to_uv) {
                // A scale hashes as before 2026-12-05, when only scales were read.
                Some(s) => format!("checkerboard {} {} {}", vec3(*color0), vec3(*color1), vec3(DVec3::new(s[0], s[1], 1.0))),
                None => format!("checkerboard {} {} {} {}", vec3(*color0), vec3(*color1), vec3(DVec3::from(to_uv[0])), vec3(DVec3::from(to_uv[1]))),
            }
            Texture::Bitmap(b) => {
                let m = b.to_uv;
                format!(
                    "bitmap {} {} {} {} {} {} {}",
                    b.content_hash,
                    b.filter.name(),
                    b.wrap.name(),
                    b.raw,
                    vec3(DVec3::from(m[0])),
                    vec3(DVec3::from(m[1])),
                    b.image.srgb
                )
            }
            Texture::Volume(v) => {
                let m = v.to_local;
                let row = |r: [f64; 4]| format!("{} {}", vec3(DVec3::new(r[0], r[1], r[2])), r[3]);
                format!("volume {} {} {} {} {} {} {}", v.content_hash, v.trilinear, v.wrap.name(), v.raw, row(m[0]), row(m[1]), row(m[2]))
            }
            Texture::RawConstant { value } => format!("rawconstant {}", vec3(*value)),
            // The attribute's values hash with the meshes that carry it (`Scene::hash`).
            Texture::MeshAttribute { name, scale, scalar } => format!("mesh_attribute {name} {scale} {scalar}"),
        }
    }

    /// A texture from a TOML inline table (`{ texture = "checkerboard", ... }`); errors as
    /// (span, message), naming the table's key.
    /// Image files are relative to `base` (the scene's folder).
    pub(crate) fn from_toml(table: &toml::Table, span: Range<usize>, base: &Path, errors: &mut Vec<(Range<usize>, String)>) -> Option<Texture> {
        let kind = match table.get("texture") {
            Some(toml::Value::String(k)) => k.clone(),
            _ => {
                errors.push((span, "a textured colour needs `texture = \"checkerboard\"`, `\"bitmap\"` or `\"volume\"`".into()));
                return None;
            }
        };
        match kind.as_str() {
            "checkerboard" => Texture::checkerboard_from_toml(table, span, errors),
            "bitmap" => Texture::bitmap_from_toml(table, span, base, errors),
            "volume" => Texture::volume_from_toml(table, span, base, errors),
            "rawconstant" => Texture::raw_constant_from_toml(table, span, errors),
            "mesh_attribute" => Texture::mesh_attribute_from_toml(table, span, errors),
            _ => {
                errors.push((span, format!("unknown texture \"{kind}\" (pathlab has checkerboard, bitmap, volume, rawconstant, mesh_attribute)")));
                None
            }
        }
    }

    /// `{ texture = "rawconstant", value = 0.5 }` or `value = [x, y, z]`: finite numbers, no
    /// range (Mitsuba checks none).
    fn raw_constant_from_toml(table: &toml::Table, span: Range<usize>, errors: &mut Vec<(Range<usize>, String)>) -> Option<Texture> {
        for key in table.keys() {
            if !["texture", "value"].contains(&key.as_str()) {
                errors.push((span.clone(), format!("unknown key `{key}` of a rawconstant (its key: value)")));
                return None;
            }
        }
        let number = |v: &toml::Value| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).filter(|x| x.is_finite());
        let value = match table.get("value") {
            None => {
                errors.push((span, "a rawconstant needs its `value` (a number or three)".into()));
                return None;
            }
            Some(v) => match v {
                toml::Value::Array(a) if a.len() == 3 => a.iter().map(number).collect::<Option<Vec<f64>>>().map(|a| DVec3::new(a[0], a[1], a[2])),
                v => number(v).map(DVec3::splat),
            },
        };
        match value {
            Some(value) => Some(Texture::RawConstant { value }),
            None => {
                errors.push((span, format!("`value` of a rawconstant must be one finite number or three (got {})", table["value"])));
                None
            }
        }
    }

    /// `{ texture = "mesh_attribute", name = "vertex_color", scale = 1.0 }`: the name starts
    /// with `vertex_` or `face_` (Mitsuba's rule), the scale is finite (default 1).
    fn mesh_attribute_from_toml(table: &toml::Table, span: Range<usize>, errors: &mut Vec<(Range<usize>, String)>) -> Option<Texture> {
        let r = TableReader::new(table, span.clone(), "mesh_attribute", &["name", "scale"], errors);
        let mut ok = r.ok;
        let name = match table.get("name") {
            Some(toml::Value::String(n)) if n.starts_with("vertex_") || n.starts_with("face_") => n.clone(),
            Some(v) => {
                errors.push((span.clone(), format!("`name` of a mesh_attribute must start with \"vertex_\" or \"face_\" (got {v})")));
                return None;
            }
            None => {
                errors.push((span, "a mesh_attribute needs the attribute's `name` (e.g. \"vertex_color\")".into()));
                return None;
            }
        };
        let scale = match table.get("scale") {
            None => 1.0,
            Some(v) => match v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).filter(|x| x.is_finite()) {
                Some(x) => x,
                None => {
                    errors.push((span, format!("`scale` of a mesh_attribute must be a finite number (got {v})")));
                    ok = false;
                    1.0
                }
            },
        };
        ok.then_some(Texture::MeshAttribute { name, scale, scalar: false })
    }

    /// The name of the mesh attribute it reads, if it is a `mesh_attribute`.
    pub fn mesh_attribute(&self) -> Option<&str> {
        match self {
            Texture::MeshAttribute { name, .. } => Some(name),
            _ => None,
        }
    }

    fn checkerboard_from_toml(table: &toml::Table, span: Range<usize>, errors: &mut Vec<(Range<usize>, String)>) -> Option<Texture> {
        let mut ok = true;
        for key in table.keys() {
            if !["texture", "color0", "color1", "to_uv_scale", "to_uv"].contains(&key.as_str()) {
                errors.push((span.clone(), format!("unknown key `{key}` of a checkerboard (its keys: color0, color1, to_uv_scale or to_uv)")));
                ok = false;
            }
        }
        let mut color = |key: &str, default: f64| -> DVec3 {
            match table.get(key) {
                None => DVec3::splat(default),
                Some(v) => match <RawColor as serde::Deserialize>::deserialize(v.clone()).ok().map(|c| c.0) {
                    Some(c) if c.iter().all(|x| x.is_finite() && *x >= 0.0) => DVec3::from(c),
                    _ => {
                        errors.push((span.clone(), format!("`{key}` of a checkerboard must be a colour >= 0 (a number or [r, g, b])")));
                        ok = false;
                        DVec3::ZERO
                    }
                },
            }
        };
        let color0 = color("color0", DEFAULT_COLOR0);
        let color1 = color("color1", DEFAULT_COLOR1);
        let to_uv_scale = match table.get("to_uv_scale") {
            None => DVec2::ONE,
            Some(toml::Value::Array(a)) if a.len() == 2 => {
                let n: Vec<Option<f64>> = a.iter().map(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64))).collect();
                match (n[0], n[1]) {
                    (Some(x), Some(y)) if x.is_finite() && y.is_finite() && x != 0.0 && y != 0.0 => DVec2::new(x, y),
                    _ => {
                        errors.push((span.clone(), "`to_uv_scale` must be two finite non-zero numbers".into()));
                        ok = false;
                        DVec2::ONE
                    }
                }
            }
            Some(_) => {
                errors.push((span.clone(), "`to_uv_scale` must be [su, sv]".into()));
                ok = false;
                DVec2::ONE
            }
        };
        let to_uv = match (table.get("to_uv"), table.contains_key("to_uv_scale")) {
            (None, _) => [[to_uv_scale.x, 0.0, 0.0], [0.0, to_uv_scale.y, 0.0]],
            (Some(_), true) => {
                errors.push((span.clone(), "give either `to_uv_scale` or `to_uv` of a checkerboard, not both".into()));
                ok = false;
                bitmap::IDENTITY_UV
            }
            (Some(v), false) => match uv_matrix(v) {
                Some(m) => m,
                None => {
                    errors.push((span.clone(), "`to_uv` of a checkerboard must be two rows of three finite numbers, [[m00, m01, m02], [m10, m11, m12]]".into()));
                    ok = false;
                    bitmap::IDENTITY_UV
                }
            },
        };
        ok.then_some(Texture::Checkerboard { color0, color1, to_uv })
    }

    fn bitmap_from_toml(table: &toml::Table, span: Range<usize>, base: &Path, errors: &mut Vec<(Range<usize>, String)>) -> Option<Texture> {
        let mut r = TableReader::new(table, span.clone(), "bitmap", &["filename", "filter_type", "wrap_mode", "raw", "to_uv"], errors);
        let filter = Filter::parse(&r.choice("filter_type", "bilinear", &["bilinear", "nearest"])).expect("a listed filter");
        let wrap = Wrap::parse(&r.choice("wrap_mode", "repeat", &["repeat", "mirror", "clamp"])).expect("a listed wrap mode");
        let raw = r.flag("raw");
        let mut ok = r.ok;
        let to_uv = match table.get("to_uv") {
            None => bitmap::IDENTITY_UV,
            Some(v) => match uv_matrix(v) {
                Some(m) => m,
                None => {
                    errors.push((span.clone(), "`to_uv` of a bitmap must be two rows of three finite numbers, [[m00, m01, m02], [m10, m11, m12]]".into()));
                    ok = false;
                    bitmap::IDENTITY_UV
                }
            },
        };
        let Some(toml::Value::String(name)) = table.get("filename") else {
            errors.push((span, "a bitmap needs `filename = \"…\"` (an image file: .png, .jpg, .hdr or .exr)".into()));
            return None;
        };
        let file = base.join(name);
        if !file.exists() {
            errors.push((span, format!("image file \"{name}\" not found (searched {}/)", base.display())));
            return None;
        }
        let image = match crate::scene::image_file::read_image(&file, raw) {
            Ok(image) => image,
            Err(e) => {
                errors.push((span, format!("image file {}: {e}", file.display())));
                return None;
            }
        };
        ok.then(|| Texture::Bitmap(Bitmap::new(file, image, filter, wrap, raw, to_uv)))
    }

    fn volume_from_toml(table: &toml::Table, span: Range<usize>, base: &Path, errors: &mut Vec<(Range<usize>, String)>) -> Option<Texture> {
        let mut r = TableReader::new(table, span.clone(), "volume", &["filename", "filter_type", "wrap_mode", "raw", "to_world", "use_grid_bbox"], errors);
        let trilinear = r.choice("filter_type", "trilinear", &["trilinear", "nearest"]) == "trilinear";
        let wrap = Wrap::parse(&r.choice("wrap_mode", "clamp", &["repeat", "mirror", "clamp"])).expect("a listed wrap mode");
        let (raw, use_grid_bbox) = (r.flag("raw"), r.flag("use_grid_bbox"));
        let mut ok = r.ok;
        // `to_world`: three rows of four numbers (an affine map), the grid's unit cube to the world.
        let to_world = match table.get("to_world") {
            None => glam::DMat4::IDENTITY,
            Some(v) => match affine_rows(v) {
                Some(m) if m.determinant().abs() > 1e-12 => m,
                _ => {
                    errors.push((span.clone(), "`to_world` of a volume must be three rows of four finite numbers, an invertible affine map".into()));
                    ok = false;
                    glam::DMat4::IDENTITY
                }
            },
        };
        let Some(toml::Value::String(name)) = table.get("filename") else {
            errors.push((span, "a volume needs `filename = \"…\"` (a Mitsuba .vol grid)".into()));
            return None;
        };
        let file = base.join(name);
        if !file.exists() {
            errors.push((span, format!("volume file \"{name}\" not found (searched {}/)", base.display())));
            return None;
        }
        let (res, channels, data, bbox) = match volume::read_vol(&file) {
            Ok(v) => v,
            Err(e) => {
                errors.push((span, format!("volume file {}: {e}", file.display())));
                return None;
            }
        };
        let mut to_local = to_world.inverse();
        if use_grid_bbox {
            // Mitsuba's bbox_transform: the file's box onto the unit cube, after to_world's inverse.
            let (lo, hi) = (glam::DVec3::new(bbox[0] as f64, bbox[1] as f64, bbox[2] as f64), glam::DVec3::new(bbox[3] as f64, bbox[4] as f64, bbox[5] as f64));
            if (hi - lo).min_element() <= 0.0 {
                errors.push((span, format!("volume file {}: its bounding box is empty, which `use_grid_bbox` cannot map", file.display())));
                return None;
            }
            to_local = glam::DMat4::from_scale((hi - lo).recip()) * glam::DMat4::from_translation(-lo) * to_local;
        }
        let rows = to_local.transpose().to_cols_array_2d();
        let to_local = [rows[0], rows[1], rows[2]];
        ok.then(|| Texture::Volume(GridVolume::new(file, res, channels, data, trilinear, wrap, raw, to_local)))
    }

    /// Its TOML inline table.
    pub fn to_toml(&self) -> toml::Value {
        match self {
            Texture::Checkerboard { color0, color1, to_uv } => {
                let mut t = toml::Table::new();
                t.insert("texture".into(), toml::Value::String("checkerboard".into()));
                let color = |c: DVec3| toml::Value::try_from(RawColor(c.to_array())).expect("a colour is a TOML value");
                t.insert("color0".into(), color(*color0));
                t.insert("color1".into(), color(*color1));
                match scale_of(to_uv) {
                    Some(s) => t.insert("to_uv_scale".into(), toml::Value::Array(vec![toml::Value::Float(s[0]), toml::Value::Float(s[1])])),
                    None => {
                        let row = |r: [f64; 3]| toml::Value::Array(r.iter().map(|&x| toml::Value::Float(x)).collect());
                        t.insert("to_uv".into(), toml::Value::Array(vec![row(to_uv[0]), row(to_uv[1])]))
                    }
                };
                toml::Value::Table(t)
            }
            Texture::Bitmap(b) => {
                let mut t = toml::Table::new();
                t.insert("texture".into(), toml::Value::String("bitmap".into()));
                t.insert("filename".into(), toml::Value::String(b.file.display().to_string()));
                t.insert("filter_type".into(), toml::Value::String(b.filter.name().into()));
                t.insert("wrap_mode".into(), toml::Value::String(b.wrap.name().into()));
                t.insert("raw".into(), toml::Value::Boolean(b.raw));
                if b.to_uv != bitmap::IDENTITY_UV {
                    let row = |r: [f64; 3]| toml::Value::Array(r.iter().map(|x| toml::Value::Float(*x)).collect());
                    t.insert("to_uv".into(), toml::Value::Array(vec![row(b.to_uv[0]), row(b.to_uv[1])]));
                }
                toml::Value::Table(t)
            }
            Texture::Volume(v) => {
                let mut t = toml::Table::new();
                t.insert("texture".into(), toml::Value::String("volume".into()));
                t.insert("filename".into(), toml::Value::String(v.file.display().to_string()));
                t.insert("filter_type".into(), toml::Value::String(if v.trilinear { "trilinear" } else { "nearest" }.into()));
                t.insert("wrap_mode".into(), toml::Value::String(v.wrap.name().into()));
                t.insert("raw".into(), toml::Value::Boolean(v.raw));
                // The grid's placement as a to_world (use_grid_bbox folded into it).
                let m = v.to_local;
                let local = glam::DMat4::from_cols_array_2d(&[m[0], m[1], m[2], [0.0, 0.0, 0.0, 1.0]]).transpose();
                let w = local.inverse().transpose().to_cols_array_2d();
                let row = |r: [f64; 4]| toml::Value::Array(r.iter().map(|x| toml::Value::Float(*x)).collect());
                t.insert("to_world".into(), toml::Value::Array(vec![row(w[0]), row(w[1]), row(w[2])]));
                toml::Value::Table(t)
            }
            Texture::RawConstant { value } => {
                let mut t = toml::Table::new();
                t.insert("texture".into(), toml::Value::String("rawconstant".into()));
                t.insert("value".into(), toml::Value::Array(value.to_array().iter().map(|x| toml::Value::Float(*x)).collect()));
                toml::Value::Table(t)
            }
            Texture::MeshAttribute { name, scale, .. } => {
                let mut t = toml::Table::new();
                t.insert("texture".into(), toml::Value::String("mesh_attribute".into()));
                t.insert("name".into(), toml::Value::String(name.clone()));
                t.insert("scale".into(), toml::Value::Float(*scale));
                toml::Value::Table(t)
            }
        }
    }
}

/// The luminance of a linear RGB value in f32, as the kernel's `texture_value_1` takes it.
pub(crate) fn luminance_f32(c: [f32; 3]) -> f32 {
    let w = crate::scene::emitters::LUMINANCE_WEIGHTS.map(|w| w as f32);
    w[0] * c[0] + w[1] * c[1] + w[2] * c[2]
}

/// `[[m00, m01, m02, m03], [..], [..]]` of finite numbers: the rows of an affine map.
fn affine_rows(v: &toml::Value) -> Option<glam::DMat4> {
    let rows = v.as_array().filter(|r| r.len() == 3)?;
    let mut m = [[0.0; 4]; 4];
    m[3][3] = 1.0;
    for (r, row) in rows.iter().enumerate() {
        let row = row.as_array().filter(|x| x.len() == 4)?;
        for (c, x) in row.iter().enumerate() {
            m[r][c] = x.as_float().or_else(|| x.as_integer().map(|i| i as f64)).filter(|x| x.is_finite())?;
        }
    }
    Some(glam::DMat4::from_cols_array_2d(&m).transpose())
}

/// The keys of a file-backed texture's TOML table, read with errors that name its kind: unknown
/// keys, a choice among names, a flag. `ok` is false once any was wrong.
struct TableReader<'a> {
    table: &'a toml::Table,
    span: Range<usize>,
    kind: &'static str,
    errors: &'a mut Vec<(Range<usize>, String)>,
    ok: bool,
}

impl<'a> TableReader<'a> {
    /// Checks that every key but `texture` is one of `keys`.
    fn new(table: &'a toml::Table, span: Range<usize>, kind: &'static str, keys: &[&str], errors: &'a mut Vec<(Range<usize>, String)>) -> TableReader<'a> {
        let mut ok = true;
        for key in table.keys().filter(|k| *k != "texture") {
            if !keys.contains(&key.as_str()) {
                errors.push((span.clone(), format!("unknown key `{key}` of a {kind} (its keys: {})", keys.join(", "))));
                ok = false;
            }
        }
        TableReader { table, span, kind, errors, ok }
    }

    /// `key`, one of `names`, else `default`.
    fn choice(&mut self, key: &str, default: &str, names: &[&str]) -> String {
        match self.table.get(key) {
            None => default.to_string(),
            Some(toml::Value::String(s)) if names.contains(&s.as_str()) => s.clone(),
            Some(v) => {
                self.errors.push((self.span.clone(), format!("`{key}` of a {} must be one of {} (got {v})", self.kind, names.join(", "))));
                self.ok = false;
                default.to_string()
            }
        }
    }

    /// `key`, true or false, else false.
    fn flag(&mut self, key: &str) -> bool {
        match self.table.get(key) {
            None => false,
            Some(toml::Value::Boolean(b)) => *b,
            Some(_) => {
                self.errors.push((self.span.clone(), format!("`{key}` of a {} must be true or false", self.kind)));
                self.ok = false;
                false
            }
        }
    }
}

/// `[[m00, m01, m02], [m10, m11, m12]]` of finite numbers.
/// The scales (su, sv) of a `to_uv` that only scales u and v.
fn scale_of(m: &[[f64; 3]; 2]) -> Option<[f64; 2]> {
    (m[0][1] == 0.0 && m[0][2] == 0.0 && m[1][0] == 0.0 && m[1][2] == 0.0).then_some([m[0][0], m[1][1]])
}

fn uv_matrix(v: &toml::Value) -> Option<[[f64; 3]; 2]> {
    let rows = v.as_array().filter(|r| r.len() == 2)?;
    let mut m = [[0.0; 3]; 2];
    for (r, row) in rows.iter().enumerate() {
        let row = row.as_array().filter(|x| x.len() == 3)?;
        for (c, x) in row.iter().enumerate() {
            m[r][c] = x.as_float().or_else(|| x.as_integer().map(|i| i as f64)).filter(|x| x.is_finite())?;
        }
    }
    Some(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_checkerboard_is_mitsubas() {
        let t = Texture::Checkerboard { color0: DVec3::splat(0.8), color1: DVec3::splat(0.2), to_uv: [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0]] };
        // (0.3, 0.2) -> (0.6, 0.2): u above 1/2, v not: color1.
        assert_eq!(t.eval([0.3, 0.2], [0.0; 3]), [0.2; 3]);
        // (0.1, 0.2) -> both below: color0; (0.3, 0.7): both above: color0.
        assert_eq!(t.eval([0.1, 0.2], [0.0; 3]), [0.8; 3]);
        assert_eq!(t.eval([0.3, 0.7], [0.0; 3]), [0.8; 3]);
        // Negative coordinates repeat: -0.1 -> fraction 0.9.
        assert_eq!(t.eval([-0.05, 0.7], [0.0; 3]), [0.8; 3]);
        assert_eq!(t.mean(), DVec3::splat(0.5));
    }
}
