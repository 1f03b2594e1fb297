//! The scene file as written: TOML deserialised with the span of every field, before validation.

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use toml::Spanned;

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScene {
    pub camera: Spanned<RawCamera>,
    pub render: Spanned<RawRender>,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, Spanned<RawMaterial>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spheres: Vec<Spanned<RawSphere>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub planes: Vec<Spanned<RawPlane>>,
    pub display: Option<Spanned<RawDisplay>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub meshes: Vec<Spanned<RawMesh>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rectangles: Vec<Spanned<RawShape>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cubes: Vec<Spanned<RawShape>>,
    /// `[[disks]]` and `[[cylinders]]`: Mitsuba's analytic `disk` and `cylinder`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub disks: Vec<Spanned<RawShape>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cylinders: Vec<Spanned<RawCylinder>>,
    /// `[[linear_curves]]`: Mitsuba's `linearcurve`, tubes along the polylines of a curve file.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub linear_curves: Vec<Spanned<RawCurve>>,
    /// `[[bspline_curves]]`: Mitsuba's `bsplinecurve`, tubes along the cubic B-splines of a
    /// curve file (the same format).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bspline_curves: Vec<Spanned<RawCurve>>,
    /// `[[sdf_grids]]`: Mitsuba's `sdfgrid`, the zero set of a signed distance grid.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sdf_grids: Vec<Spanned<RawSdfGrid>>,
    /// `[environment_map]`: Mitsuba's `envmap`.
    pub environment_map: Option<Spanned<RawEnvironmentMap>>,
    /// `[techniques]`: researchers' sampling techniques loaded with the scene.
    pub techniques: Option<Spanned<RawTechniques>>,
    /// Delta lights: Mitsuba's `point`, `spot` and `directional`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub point_lights: Vec<Spanned<RawPointLight>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spot_lights: Vec<Spanned<RawSpotLight>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub directional_lights: Vec<Spanned<RawDirectionalLight>>,
    /// Mitsuba's `projector`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub projector_lights: Vec<Spanned<RawProjectorLight>>,
    /// `[media.<name>]`: participating media (Mitsuba's `homogeneous`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub media: BTreeMap<String, Spanned<RawMedium>>,
}

impl RawScene {
    /// The files its shapes read (meshes, curves, grids), for rewriting them relative to
    /// another folder.
    pub fn shape_files_mut(&mut self) -> impl Iterator<Item = &mut Spanned<String>> {
        let meshes = self.meshes.iter_mut().map(|m| &mut m.get_mut().file);
        let curves = self.linear_curves.iter_mut().chain(self.bspline_curves.iter_mut()).map(|c| &mut c.get_mut().file);
        let grids = self.sdf_grids.iter_mut().map(|g| &mut g.get_mut().file);
        meshes.chain(curves).chain(grids)
    }
}

/// `[media.<name>]`: a medium. `type` is `homogeneous` (the default) or `heterogeneous`;
/// extinction `sigma_t` (a number or `[r, g, b]`, per unit length, or, in a heterogeneous
/// medium, a volume texture table) times `scale` (default 1); single-scattering `albedo`
/// (default 0.75, Mitsuba's; a number, `[r, g, b]` or a volume texture table); in a
/// heterogeneous medium of constant `sigma_t`, the box it fills, `bounds = [[min], [max]]`
/// (default the unit cube, Mitsuba's constvolume's); its phase function, `isotropic` (the
/// default) or `hg` with mean cosine `g`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMedium {
    #[serde(default, rename = "type", skip_serializing_if = "Option::is_none")]
    pub kind: Option<Spanned<String>>,
    pub sigma_t: Spanned<RawColorOrTexture>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Spanned<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub albedo: Option<Spanned<RawColorOrTexture>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounds: Option<Spanned<[[f64; 3]; 2]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase: Option<Spanned<String>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub g: Option<Spanned<f64>>,
}

/// `[[point_lights]]`: a point light of `intensity` (W/sr) at `position`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPointLight {
    pub position: Spanned<[f64; 3]>,
    pub intensity: Spanned<RawColor>,
}

/// `[[spot_lights]]`: a spot light at `position` shining along `direction`, with Mitsuba's
/// `cutoff_angle` and `beam_width` in degrees (defaults 20 and 3/4 of the cutoff).
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSpotLight {
    pub position: Spanned<[f64; 3]>,
    pub direction: Spanned<[f64; 3]>,
    pub intensity: Spanned<RawColor>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutoff_angle: Option<Spanned<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beam_width: Option<Spanned<f64>>,
    /// A texture projected along the cone (Mitsuba's `texture`), oriented by `up` (the light
    /// frame's y axis; required with a texture).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<Spanned<toml::Value>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Spanned<[f64; 3]>>,
}

/// `[[directional_lights]]`: `irradiance` arriving along `direction` (the way the light
/// travels) from infinity.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDirectionalLight {
    pub direction: Spanned<[f64; 3]>,
    pub irradiance: Spanned<RawColor>,
}

/// `[[projector_lights]]`: a projector at `position` projecting along `direction`, the image's
/// up towards `up`, with one field of view (as the camera's keys give it, resolved at the
/// image's aspect ratio), its `irradiance` (a colour or a texture table) and `scale`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawProjectorLight {
    pub position: Spanned<[f64; 3]>,
    pub direction: Spanned<[f64; 3]>,
    pub up: Spanned<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_x: Option<Spanned<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_y: Option<Spanned<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_smaller: Option<Spanned<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_larger: Option<Spanned<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_diagonal: Option<Spanned<f64>>,
    pub irradiance: Spanned<toml::Value>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Spanned<f64>>,
}

/// `[techniques]`: WGSL files by kind (relative to the scene's folder), as `--technique
/// KIND:FILE` would give them.
#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTechniques {
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bsdf: Vec<Spanned<String>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub light: Vec<Spanned<String>>,
}

/// `[environment_map]`: a latitude-longitude image lighting the scene from infinity.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEnvironmentMap {
    /// The image file (relative to the scene's folder).
    pub filename: Spanned<String>,
    /// A factor on its radiance (default 1).
    pub scale: Option<Spanned<f64>>,
    /// Its frame in the world: a rotation (default: the image's top row looks along +y).
    pub transform: Option<Spanned<RawTransform>>,
}

/// `[[meshes]]`: a triangle mesh from an OBJ or PLY file.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMesh {
    pub file: Spanned<String>,
    pub material: Spanned<String>,
    pub transform: Option<Spanned<RawTransform>>,
    /// Flat shading with the face normals (default false: the file's vertex normals, or smooth
    /// ones recomputed where it has none, as Mitsuba's `face_normals`).
    pub face_normals: Option<Spanned<bool>>,
    /// Reverses every triangle's winding: the front side (of emission and of one-sided
    /// materials) becomes the back (Mitsuba's `flip_normals`).
    pub flip_normals: Option<Spanned<bool>>,
    /// An emissive mesh emits on both sides (default: on its front only).
    pub two_sided_emission: Option<Spanned<bool>>,
    /// Texture coordinates' v becomes 1 - v (default true for OBJ and PLY, as Mitsuba's
    /// `flip_tex_coords`; false for serialized files, which Mitsuba never flips).
    pub flip_tex_coords: Option<Spanned<bool>>,
    /// Which shape of a Mitsuba serialized file (default 0, the first).
    pub shape_index: Option<Spanned<i64>>,
}

/// `[[rectangles]]`, `[[cubes]]` and `[[disks]]`: Mitsuba's built-in shapes.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawShape {
    pub material: Spanned<String>,
    pub transform: Option<Spanned<RawTransform>>,
    pub flip_normals: Option<Spanned<bool>>,
    pub two_sided_emission: Option<Spanned<bool>>,
}

/// `[[linear_curves]]` (Mitsuba's `linearcurve`) and `[[bspline_curves]]` (Mitsuba's
/// `bsplinecurve`): the curves of `file` (relative to the scene
/// file; Mitsuba's text format, a control point `x y z radius` per line, a blank line between
/// curves), their points moved by `transform` (their radii kept, as Mitsuba does).
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCurve {
    pub file: Spanned<String>,
    pub material: Spanned<String>,
    pub transform: Option<Spanned<RawTransform>>,
}

/// `[[sdf_grids]]`: Mitsuba's `sdfgrid`: the signed distances of a `.vol` file (`file`,
/// relative to the scene file; one channel) at the nodes of a grid on the unit cube, which
/// `transform` places; `normals` "smooth" (default) or "analytic".
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSdfGrid {
    pub file: Spanned<String>,
    pub material: Spanned<String>,
    pub transform: Option<Spanned<RawTransform>>,
    pub normals: Option<Spanned<String>>,
}

/// `[[cylinders]]`: Mitsuba's `cylinder` from `p0` (default the origin) to `p1` (default
/// [0, 0, 1]) of `radius` (default 1), then moved by `transform`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCylinder {
    pub material: Spanned<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p0: Option<Spanned<[f64; 3]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p1: Option<Spanned<[f64; 3]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<Spanned<f64>>,
    pub transform: Option<Spanned<RawTransform>>,
    pub flip_normals: Option<Spanned<bool>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub two_sided_emission: Option<Spanned<bool>>,
}

/// An object-to-world transform: `scale`, then `rotate` (one rotation or a list, applied in
/// the order written), then `translate`; or a 4x4 `matrix` alone.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTransform {
    pub translate: Option<Spanned<[f64; 3]>>,
    pub rotate: Option<Spanned<RawRotations>>,
    pub scale: Option<Spanned<RawScale>>,
    pub matrix: Option<Spanned<[[f64; 4]; 4]>>,
}

/// A rotation by `angle` degrees about `axis` (right-handed).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRotation {
    pub axis: [f64; 3],
    pub angle: f64,
}

/// One rotation or a list of them.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum RawRotations {
    One(RawRotation),
    Many(Vec<RawRotation>),
}

/// A uniform scale factor or one per axis.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum RawScale {
    Uniform(f64),
    PerAxis([f64; 3]),
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDisplay {
    pub transfer: Option<Spanned<String>>,
    pub gamma: Option<Spanned<f64>>,
    pub exposure: Option<Spanned<f64>>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCamera {
    pub position: Spanned<[f64; 3]>,
    pub look_at: Spanned<[f64; 3]>,
    pub up: Spanned<[f64; 3]>,
    pub fov_x: Option<Spanned<f64>>,
    pub fov_y: Option<Spanned<f64>>,
    /// Mitsuba's `fov_axis` rules `smaller`, `larger` and `diagonal`, kept as written.
    pub fov_smaller: Option<Spanned<f64>>,
    pub fov_larger: Option<Spanned<f64>>,
    pub fov_diagonal: Option<Spanned<f64>>,
    /// An orthographic camera, instead of a field of view: the width of the view in scene units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orthographic_width: Option<Spanned<f64>>,
    /// A thin lens: the aperture's radius (default 0, a pinhole) and the distance of the plane
    /// in focus (default the distance to `look_at`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aperture_radius: Option<Spanned<f64>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focus_distance: Option<Spanned<f64>>,
    /// The medium the camera sits in (a name of `[media]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub medium: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRender {
    pub width: Spanned<i64>,
    pub height: Spanned<i64>,
    pub max_depth: Spanned<i64>,
    pub rr_depth: Option<Spanned<i64>>,
    pub environment: Option<Spanned<RawColor>>,
    pub spp: Option<Spanned<i64>>,
    /// Mitsuba's `hide_emitters`: camera rays see through area emitters and see no environment.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hide_emitters: Option<Spanned<bool>>,
}

/// `[materials.<name>]`: what every material has (`emission`, `two_sided`, `opacity`, `normal_map`, `bump_map`, `back`, `blend`, `blend_weight`, the `bsdf` kind) and
/// the fields of its BSDF kind, kept as written with their spans: the kind's file reads them
/// (`scene::bsdfs`), so that a new kind adds its fields without touching this file.
#[derive(Debug, Default)]
pub(crate) struct RawMaterial {
    pub emission: Option<Spanned<RawColorOrTexture>>,
    /// Whether the back of a surface scatters too (default true); Mitsuba's BSDFs are
    /// one-sided unless wrapped in `twosided`.
    pub two_sided: Option<Spanned<bool>>,
    /// The kind's `TOML_NAME` (`phong`, the default, `conductor`, `roughconductor`, ...).
    pub bsdf: Option<Spanned<String>>,
    /// Mitsuba's `mask`: a number in [0, 1] or a texture table (`bsdfs::Opacity`).
    pub opacity: Option<Spanned<toml::Value>>,
    /// Mitsuba's `normalmap`: a texture table (`bsdfs::NormalMap`).
    pub normal_map: Option<Spanned<toml::Value>>,
    /// Mitsuba's `bumpmap`: a texture table with its `scale` (`bsdfs::BumpMap`).
    pub bump_map: Option<Spanned<toml::Value>>,
    /// Mitsuba's `twosided` with two BSDFs: the name of the material whose BSDF scatters on the
    /// back.
    pub back: Option<Spanned<String>>,
    /// Mitsuba's `blendbsdf`: the name of the material whose BSDF is blended with this one's,
    /// and its weight (a number in [0, 1] or a texture table, `bsdfs::Blend`).
    pub blend: Option<Spanned<String>>,
    pub blend_weight: Option<Spanned<toml::Value>>,
    /// The media the surface bounds (names of `[media]`): `interior` on the side its normal
    /// points away from, `exterior` on the other.
    pub interior: Option<Spanned<String>>,
    pub exterior: Option<Spanned<String>>,
    /// The BSDF's fields, in the order written.
    pub params: Vec<(String, Spanned<toml::Value>)>,
}

impl<'de> Deserialize<'de> for RawMaterial {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct MaterialVisitor;
        impl<'de> Visitor<'de> for MaterialVisitor {
            type Value = RawMaterial;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a material table")
            }
            fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<RawMaterial, A::Error> {
                let mut m = RawMaterial::default();
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "emission" => m.emission = Some(map.next_value()?),
                        "two_sided" => m.two_sided = Some(map.next_value()?),
                        "bsdf" => m.bsdf = Some(map.next_value()?),
                        "opacity" => m.opacity = Some(map.next_value()?),
                        "normal_map" => m.normal_map = Some(map.next_value()?),
                        "bump_map" => m.bump_map = Some(map.next_value()?),
                        "back" => m.back = Some(map.next_value()?),
                        "blend" => m.blend = Some(map.next_value()?),
                        "blend_weight" => m.blend_weight = Some(map.next_value()?),
                        "interior" => m.interior = Some(map.next_value()?),
                        "exterior" => m.exterior = Some(map.next_value()?),
                        _ => {
                            let value = map.next_value()?;
                            m.params.push((key, value));
                        }
                    }
                }
                Ok(m)
            }
        }
        deserializer.deserialize_map(MaterialVisitor)
    }
}

/// The BSDF's kind and fields first, then emission and sidedness.
impl Serialize for RawMaterial {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = serializer.serialize_map(None)?;
        if let Some(b) = &self.bsdf {
            map.serialize_entry("bsdf", b.get_ref())?;
        }
        for (k, v) in &self.params {
            map.serialize_entry(k, v.get_ref())?;
        }
        if let Some(e) = &self.emission {
            map.serialize_entry("emission", e.get_ref())?;
        }
        if let Some(t) = &self.two_sided {
            map.serialize_entry("two_sided", t.get_ref())?;
        }
        if let Some(o) = &self.opacity {
            map.serialize_entry("opacity", o.get_ref())?;
        }
        if let Some(n) = &self.normal_map {
            map.serialize_entry("normal_map", n.get_ref())?;
        }
        if let Some(b) = &self.bump_map {
            map.serialize_entry("bump_map", b.get_ref())?;
        }
        if let Some(b) = &self.back {
            map.serialize_entry("back", b.get_ref())?;
        }
        if let Some(b) = &self.blend {
            map.serialize_entry("blend", b.get_ref())?;
        }
        if let Some(w) = &self.blend_weight {
            map.serialize_entry("blend_weight", w.get_ref())?;
        }
        if let Some(m) = &self.interior {
            map.serialize_entry("interior", m.get_ref())?;
        }
        if let Some(m) = &self.exterior {
            map.serialize_entry("exterior", m.get_ref())?;
        }
        map.end()
    }
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSphere {
    pub center: Spanned<[f64; 3]>,
    pub radius: Spanned<f64>,
    pub material: Spanned<String>,
    /// The sphere's object axes in world space (rows x, y, z), which place its uv
    /// parametrisation; the world's axes when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axes: Option<Spanned<[[f64; 3]; 3]>>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPlane {
    pub point: Spanned<[f64; 3]>,
    pub normal: Spanned<[f64; 3]>,
    pub material: Spanned<String>,
}

/// A colour, or a texture table: a material's `emission` (Mitsuba's area emitter with a
/// textured `radiance`), `{ texture = "bitmap", filename = "sky.exr" }`; a medium's `sigma_t`
/// or `albedo`, `{ texture = "volume", filename = "density.vol" }`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum RawColorOrTexture {
    Color(RawColor),
    Texture(toml::Table),
}

impl Serialize for RawColorOrTexture {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            RawColorOrTexture::Color(c) => c.serialize(serializer),
            RawColorOrTexture::Texture(t) => t.serialize(serializer),
        }
    }
}

/// A table is a texture; anything else is read as a colour.
impl<'de> Deserialize<'de> for RawColorOrTexture {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        match toml::Value::deserialize(deserializer)? {
            toml::Value::Table(table) => Ok(RawColorOrTexture::Texture(table)),
            other => RawColor::deserialize(other)
                .map(RawColorOrTexture::Color)
                .map_err(|e| de::Error::custom(format!("{} (or a texture table, {{ texture = \"bitmap\", ... }})", e.to_string().trim_end()))),
        }
    }
}

/// An RGB colour written either as `[r, g, b]` or as one number for all three channels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RawColor(pub [f64; 3]);

/// Written back as one number when the channels agree, else as `[r, g, b]`.
impl Serialize for RawColor {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let [r, g, b] = self.0;
        if r == g && g == b { serializer.serialize_f64(r) } else { self.0.serialize(serializer) }
    }
}

impl<'de> Deserialize<'de> for RawColor {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ColorVisitor;
        impl<'de> Visitor<'de> for ColorVisitor {
            type Value = RawColor;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of 3 numbers [r, g, b]")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawColor, E> {
                Ok(RawColor([v; 3]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawColor, E> {
                Ok(RawColor([v as f64; 3]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawColor, E> {
                Ok(RawColor([v as f64; 3]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawColor, A::Error> {
                let mut rgb = [0.0; 3];
                for (i, c) in rgb.iter_mut().enumerate() {
                    *c = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<f64>()?.is_some() {
                    return Err(de::Error::invalid_length(4, &self));
                }
                Ok(RawColor(rgb))
            }
        }
        deserializer.deserialize_any(ColorVisitor)
    }
}
