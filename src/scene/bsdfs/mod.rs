//! BSDFs, one file per kind, as Mitsuba 3 lays out `src/bsdfs/`. A kind's Rust file
//! (`phong.rs`, `conductor.rs`, `rough_conductor.rs`, `dielectric.rs`, `plastic.rs`,
//! `rough_dielectric.rs`, `thin_dielectric.rs`, `rough_plastic.rs`, `principled.rs`,
//! `polarized_plastic.rs`, `principled_thin.rs`) owns
//! everything the host knows of it: its validated parameters, the fields of its TOML material,
//! the properties of its Mitsuba plugins, its lines of the scene hash and its parameter block
//! for the kernel. Its WGSL file,
//! `shaders/bsdfs/<stem>.wgsl` (with `eval_pdf_<stem>_bsdf` and `sample_<stem>_bsdf`), is listed
//! in `shaders::files::BSDF_KINDS`.
//!
//! The registry below is the one list a new kind joins. From it come `BsdfKind` (the kinds'
//! numbers, `BSDF_KIND_*` in WGSL), `Bsdf` (a material's validated BSDF), one `HAS_<KIND>`
//! override per kind (a pipeline compiles only the kinds its scene uses) and the kernel's
//! dispatch (`shaders::bsdf_dispatch`). See the README's "Adding a BSDF".
//!
//! Mitsuba's `mask` (`mask.rs`, `shaders/bsdfs/mask.wgsl`) wraps any kind: it is a material's
//! opacity, not a kind. Likewise `normalmap` (`normal_map.rs`) and `bumpmap` (`bump_map.rs`):
//! a material's perturbed shading frame. And `blendbsdf` (`blend.rs`): a material's blend with
//! another material's BSDF, one of the two picked per path vertex.

mod blend;
mod bump_map;
mod conductor;
mod dielectric;
mod distribution;
mod fresnel;
mod ior;
mod mask;
mod normal_map;
mod named_conductors;
mod phong;
mod plastic;
mod plugin;
mod polarized_plastic;
mod principled;
mod principled_thin;
mod rough_conductor;
mod rough_dielectric;
mod rough_plastic;
mod thin_dielectric;

use std::ops::Range;
use std::sync::OnceLock;

use toml::Spanned;

use super::checker::Checker;

pub use blend::Blend;
pub use bump_map::{BumpMap, DEFAULT_BUMP_SCALE};
pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use distribution::{Distribution, Roughness};
pub use ior::NAMED_IORS;
pub use mask::{Opacity, DEFAULT_MITSUBA_OPACITY};
pub use normal_map::NormalMap;
pub use named_conductors::NAMED_CONDUCTORS;
pub use phong::Phong;
pub use plastic::{fresnel_diffuse_reflectance, Plastic};
pub use polarized_plastic::PolarizedPlastic;
pub use principled::{Principled, Weight as PrincipledWeight};
pub use principled_thin::PrincipledThin;
pub use rough_conductor::RoughConductor;
pub use rough_dielectric::RoughDielectric;
pub use rough_plastic::{CoatingTables, RoughPlastic, TRANSMITTANCE_RES as ROUGH_PLASTIC_TABLE_RES};
pub use thin_dielectric::ThinDielectric;
pub(crate) use phong::DEFAULT_REFLECTANCE;
pub use plugin::{BsdfData, BsdfParams};
pub(crate) use plugin::{color_value, BsdfPlugin, Fields, PluginProps};

/// The registry: one line per kind (its variant, its name in messages and headers, its type).
/// The first kind is the default of a TOML material without `bsdf`.
macro_rules! bsdf_registry {
    ($( $(#[doc = $doc:expr])* $variant:ident = $name:literal => $ty:ty ),+ $(,)?) => {
        crate::names::named_enum! {
            /// The kind of a material's BSDF (`Bsdf::kind`).
            pub enum BsdfKind("BSDF kind") {
                $( $(#[doc = $doc])* $variant = $name ),+
            }
        }

        /// A material's BSDF: its kind with that kind's validated parameters.
        #[derive(Debug, Clone, PartialEq)]
        pub enum Bsdf {
            $( $(#[doc = $doc])* $variant($ty) ),+
        }

        impl BsdfKind {
            /// Its `bsdf = "…"` in a TOML material.
            pub fn toml_name(self) -> &'static str {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::TOML_NAME ),+ }
            }

            /// The fields of its TOML material (besides `emission`, `two_sided`, `bsdf`).
            pub fn fields(self) -> &'static [&'static str] {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::FIELDS ),+ }
            }

            /// The Mitsuba plugins it reads.
            pub fn mitsuba_plugins(self) -> &'static [&'static str] {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::MITSUBA_PLUGINS ),+ }
            }

            /// Whether the kind's only lobe is a delta: next event estimation cannot
            /// contribute, and only its own sampling finds its directions.
            pub fn is_delta(self) -> bool {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::IS_DELTA ),+ }
            }

            /// Whether it has a delta lobe beside smooth ones (`BsdfPlugin::HAS_DELTA_LOBE`).
            pub fn has_delta_lobe(self) -> bool {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::HAS_DELTA_LOBE ),+ }
            }

            /// Whether it samples microfacet normals by `--microfacet-sampling`.
            pub fn has_microfacets(self) -> bool {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::MICROFACETS ),+ }
            }

            /// Whether it chooses between layered lobes by `--lobe-selection`.
            pub fn selects_lobes(self) -> bool {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::SELECTS_LOBES ),+ }
            }

            /// The slots of its parameter block whose colour may be a texture.
            pub fn texture_slots(self) -> &'static [usize] {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::TEXTURE_SLOTS ),+ }
            }

            /// The scalar parameters (slot, component) that may be a texture.
            pub fn scalar_texture_slots(self) -> &'static [(usize, usize)] {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::SCALAR_TEXTURE_SLOTS ),+ }
            }

            /// Whether it may transmit (refract into the surface).
            pub fn transmits(self) -> bool {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::TRANSMITS ),+ }
            }

            /// Whether it scatters on both sides by its nature (a dielectric).
            pub fn both_sides(self) -> bool {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::BOTH_SIDES ),+ }
            }

            /// Whether its materials' transmission depends on their parameters
            /// (`BsdfPlugin::TRANSMITS_BY_PARAMETERS`).
            pub fn transmits_by_parameters(self) -> bool {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::TRANSMITS_BY_PARAMETERS ),+ }
            }

            /// Whether a material of the kind with these fields (a Mitsuba plugin's, as
            /// `read_mitsuba` gave them) transmits, or scatters on both sides by its nature.
            pub(crate) fn fields_transmit_or_both_sides(self, fields: &[(&str, toml::Value)]) -> bool {
                self.transmits() || self.both_sides() || match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::fields_transmit(fields) ),+ }
            }

            fn read_fields(self, f: &mut Fields) -> Bsdf {
                match self { $( BsdfKind::$variant => Bsdf::$variant(<$ty as BsdfPlugin>::from_fields(f)) ),+ }
            }

            pub(crate) fn read_mitsuba(self, p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>> {
                match self { $( BsdfKind::$variant => <$ty as BsdfPlugin>::from_mitsuba(p) ),+ }
            }
        }

        impl Bsdf {
            /// Its kind.
            pub fn kind(&self) -> BsdfKind {
                match self { $( Bsdf::$variant(_) => BsdfKind::$variant ),+ }
            }

            /// Its lines of the scene hash, each `(field, value)`.
            pub fn hash_lines(&self, line: &mut dyn FnMut(&str, String)) {
                match self { $( Bsdf::$variant(b) => b.hash_lines(line) ),+ }
            }

            /// Its parameter block for the kernel, its further numbers appended to `data`.
            pub fn pack(&self, data: &mut BsdfData) -> BsdfParams {
                match self { $( Bsdf::$variant(b) => b.pack(data) ),+ }
            }

            /// Whether it reads the hit's uv parametrisation (a texture).
            pub fn reads_uv(&self) -> bool {
                match self { $( Bsdf::$variant(b) => b.reads_uv() ),+ }
            }

            /// Its parameters' textures.
            pub fn textures(&self) -> Vec<&crate::scene::Texture> {
                match self { $( Bsdf::$variant(b) => b.textures() ),+ }
            }

            /// Whether it may transmit (refract into the surface): its kind's `TRANSMITS`, or,
            /// for a kind whose transmission depends on its parameters, this material's.
            pub fn transmits(&self) -> bool {
                match self { $( Bsdf::$variant(b) => b.transmits() ),+ }
            }

            /// Whether it scatters on both sides: its kind's `BOTH_SIDES`, or a material that
            /// transmits by its parameters (a principled BSDF with `spec_trans`).
            pub fn both_sides(&self) -> bool {
                self.kind().both_sides() || (self.kind().transmits_by_parameters() && self.transmits())
            }
        }
    };
}

bsdf_registry! {
    /// The normalised modified Phong BRDF (the study's); `diffuse` is Phong without a lobe.
    Phong = "phong" => Phong,
    /// Mitsuba's smooth `conductor`: a mirror with the Fresnel term of a complex index.
    Conductor = "conductor" => Conductor,
    /// Mitsuba's `roughconductor`: Torrance-Sparrow microfacet reflection.
    RoughConductor = "rough-conductor" => RoughConductor,
    /// Mitsuba's smooth `dielectric`: Fresnel reflection and refraction, two delta lobes.
    Dielectric = "dielectric" => Dielectric,
    /// Mitsuba's smooth `plastic`: a diffuse base under a dielectric coating's delta lobe.
    Plastic = "plastic" => Plastic,
    /// Mitsuba's `roughdielectric`: microfacet reflection and refraction (Walter et al. 2007).
    RoughDielectric = "rough-dielectric" => RoughDielectric,
    /// Mitsuba's `thindielectric`: a thin pane, reflecting or passing straight through.
    ThinDielectric = "thin-dielectric" => ThinDielectric,
    /// Mitsuba's `roughplastic`: a diffuse base under a rough dielectric coating.
    RoughPlastic = "rough-plastic" => RoughPlastic,
    /// Mitsuba's `principled`: the Disney principled BRDF (diffuse with retro-reflection, sheen,
    /// a metallic and tinted GGX specular, a GTR1 clearcoat).
    Principled = "principled" => Principled,
    /// Mitsuba's `pplastic` as its RGB variants render it: rough specular reflection plus a
    /// diffuse base behind two smooth refractions, without internal reflections.
    PolarizedPlastic = "polarized-plastic" => PolarizedPlastic,
    /// Mitsuba's `principledthin`: the principled BSDF of a thin sheet (specular and diffuse
    /// transmission without refraction, both sides alike).
    PrincipledThin = "principled-thin" => PrincipledThin,
}

impl BsdfKind {
    /// The stem of its WGSL file and functions (`rough_conductor`): its name with `_` for `-`.
    pub fn stem(self) -> &'static str {
        static STEMS: OnceLock<Vec<String>> = OnceLock::new();
        &STEMS.get_or_init(|| BsdfKind::ALL.iter().map(|k| k.name().replace('-', "_")).collect())[self as usize]
    }

    /// The pipeline constant saying some material of a kind with `TRANSMITS_BY_PARAMETERS`
    /// transmits (`PRINCIPLED_TRANSMITS`).
    pub fn transmits_override(self) -> &'static str {
        static NAMES: OnceLock<Vec<String>> = OnceLock::new();
        &NAMES.get_or_init(|| BsdfKind::ALL.iter().map(|k| format!("{}_TRANSMITS", k.stem().to_uppercase())).collect())[self as usize]
    }

    /// The pipeline constant that compiles the kind in (`HAS_ROUGH_CONDUCTOR`).
    pub fn has_override(self) -> &'static str {
        static NAMES: OnceLock<Vec<String>> = OnceLock::new();
        &NAMES.get_or_init(|| BsdfKind::ALL.iter().map(|k| format!("HAS_{}", k.stem().to_uppercase())).collect())[self as usize]
    }

    /// The pipeline constant saying which of the kind's texture slots (its `texture_slots`, then
    /// its `scalar_texture_slots`, bit i the i-th) some material of the scene gives a texture
    /// (`TEXTURED_ROUGH_CONDUCTOR`): the others are not looked up.
    pub fn textured_override(self) -> &'static str {
        static NAMES: OnceLock<Vec<String>> = OnceLock::new();
        &NAMES.get_or_init(|| BsdfKind::ALL.iter().map(|k| format!("TEXTURED_{}", k.stem().to_uppercase())).collect())[self as usize]
    }

    /// The bit of this kind in a set of kinds (`SceneFeatures::bsdf_kinds`).
    pub fn bit(self) -> u32 {
        1 << self.constant()
    }

    /// The kind whose TOML name is `name`.
    pub fn from_toml_name(name: &str) -> Option<BsdfKind> {
        BsdfKind::ALL.into_iter().find(|k| k.toml_name() == name)
    }

    /// The kind that reads the Mitsuba plugin `plugin`.
    pub fn from_mitsuba_plugin(plugin: &str) -> Option<BsdfKind> {
        BsdfKind::ALL.into_iter().find(|k| k.mitsuba_plugins().contains(&plugin))
    }

    /// Every Mitsuba plugin some kind reads, for messages.
    pub fn all_mitsuba_plugins() -> Vec<&'static str> {
        BsdfKind::ALL.iter().flat_map(|k| k.mitsuba_plugins().iter().copied()).collect()
    }
}

impl Bsdf {
    /// Which of its kind's texture slots hold a texture (bit i: the i-th of the kind's
    /// `texture_slots` then `scalar_texture_slots`): read off its packed block, where a texture
    /// is a negative reference.
    pub fn textured_slots(&self) -> u16 {
        if !self.reads_uv() {
            return 0;
        }
        let block = self.pack(&mut BsdfData::default());
        let kind = self.kind();
        let colour = kind.texture_slots().iter().map(|&s| block[s][0] < 0.0);
        let scalar = kind.scalar_texture_slots().iter().map(|&(s, c)| block[s][c] < 0.0);
        colour.chain(scalar).enumerate().fold(0, |bits, (i, textured)| bits | ((textured as u16) << i))
    }

    /// The distribution of microfacet normals it draws, for a rough kind (principled: GGX).
    pub fn microfacet_distribution(&self) -> Option<Distribution> {
        match self {
            Bsdf::RoughConductor(c) => Some(c.distribution),
            Bsdf::RoughDielectric(d) => Some(d.distribution),
            Bsdf::RoughPlastic(p) => Some(p.distribution),
            Bsdf::Principled(_) => Some(Distribution::Ggx),
            Bsdf::PolarizedPlastic(p) => Some(p.distribution),
            Bsdf::PrincipledThin(_) => Some(Distribution::Ggx),
            _ => None,
        }
    }

    /// Whether its roughness differs along the surface's dp/du and across it (Mitsuba's
    /// `alpha_u` and `alpha_v`): the kernel then carries tangent frames (`SceneFeatures::
    /// anisotropic_roughness`).
    pub fn is_anisotropic(&self) -> bool {
        match self {
            Bsdf::RoughConductor(c) => c.roughness.is_anisotropic(),
            Bsdf::RoughDielectric(d) => d.roughness.is_anisotropic(),
            Bsdf::Principled(p) => p.anisotropic.value > 0.0 || p.anisotropic.texture.is_some(),
            Bsdf::PolarizedPlastic(p) => p.roughness.is_anisotropic(),
            Bsdf::PrincipledThin(p) => p.is_anisotropic(),
            _ => false,
        }
    }

    /// The Phong parameters, for the kind that has them.
    pub fn as_phong(&self) -> Option<&Phong> {
        match self {
            Bsdf::Phong(p) => Some(p),
            _ => None,
        }
    }
}

/// A material's BSDF from its TOML fields: the kind its `bsdf` names (the first kind's without
/// one), fields of another kind refused saying which kind has them, then the kind's own check.
pub(super) fn read(
    ck: &mut Checker,
    material: &str,
    span: Range<usize>,
    bsdf: Option<&Spanned<String>>,
    params: &[(String, Spanned<toml::Value>)],
) -> Bsdf {
    let field = |f: &str| format!("materials.{material}.{f}");
    let kind = match bsdf {
        None => BsdfKind::ALL[0],
        Some(b) => match BsdfKind::from_toml_name(b.get_ref()) {
            Some(k) => k,
            None => {
                let known: Vec<String> = BsdfKind::ALL.iter().map(|k| format!("\"{}\"", k.toml_name())).collect();
                ck.error(b.span(), field("bsdf"), format!("unknown bsdf \"{}\" (known: {})", b.get_ref(), known.join(", ")));
                BsdfKind::ALL[0]
            }
        },
    };
    for (name, value) in params {
        if kind.fields().contains(&name.as_str()) {
            continue;
        }
        let owners: Vec<String> =
            BsdfKind::ALL.iter().filter(|k| k.fields().contains(&name.as_str())).map(|k| format!("bsdf = \"{}\"", k.toml_name())).collect();
        let message = if owners.is_empty() {
            format!(
                "unknown field `{name}` of a {} material (its fields: {}; every material's: emission, two_sided, bsdf)",
                kind.toml_name(),
                kind.fields().join(", ")
            )
        } else {
            format!("`{name}` is not a field of a {} material: it belongs to {}", kind.toml_name(), owners.join(" and "))
        };
        ck.error(value.span(), field(name), message);
    }
    let mut f = Fields::new(ck, material, span, params);
    kind.read_fields(&mut f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_its_own_stem_override_file_and_names() {
        for k in BsdfKind::ALL {
            assert_eq!(k.has_override(), format!("HAS_{}", k.stem().to_uppercase()));
            assert_eq!(BsdfKind::from_toml_name(k.toml_name()), Some(k));
            for p in k.mitsuba_plugins() {
                assert_eq!(BsdfKind::from_mitsuba_plugin(p), Some(k));
            }
        }
    }
}
