//! What a kind of BSDF implements (`BsdfPlugin`), and what it is given to read its parameters:
//! a TOML material's fields (`Fields`) and a Mitsuba plugin's properties (`PluginProps`).

use std::ops::Range;

use glam::DVec3;
use toml::Spanned;

pub use crate::scene::bsdf_data::BsdfData;
use crate::scene::checker::Checker;
use crate::scene::textures::Texture;
use crate::scene::raw::RawColor;

/// The parameter block of one material's BSDF as the kernel reads it (`Material.p0..p3` in
/// scene.wgsl): four slots of four numbers, whose meaning the kind's two files agree on.
pub type BsdfParams = [[f32; 4]; 4];

/// What each kind of BSDF implements (one file each in `scene/bsdfs/`).
pub(crate) trait BsdfPlugin: Sized {
    /// Its `bsdf = "…"` in a TOML material.
    const TOML_NAME: &'static str;
    /// The fields of its TOML material, besides every material's `emission`, `two_sided` and
    /// `bsdf`.
    const FIELDS: &'static [&'static str];
    /// The Mitsuba plugins it reads (`<bsdf type="…">`).
    const MITSUBA_PLUGINS: &'static [&'static str];
    /// Its only lobe is a delta (a mirror): next event estimation cannot contribute, and only its
    /// own sampling finds its directions.
    const IS_DELTA: bool;
    /// Beside its smooth lobes it has a delta lobe (plastic's coating), which a generic
    /// strategy (uniform, cosine) cannot find: the kind's WGSL file then has
    /// `delta_lobe_prob_<stem>_bsdf`, the probability with which its own sampling picks that
    /// lobe (it must pick it exactly when `u_lobe` is below it), and the generic strategies
    /// draw the delta lobe with that probability and their own direction otherwise.
    const HAS_DELTA_LOBE: bool = false;
    /// It chooses between a coating's and a base's lobes (Mitsuba's plastics), with the
    /// pipeline's `LOBE_SELECTION` (`--lobe-selection`).
    const SELECTS_LOBES: bool = false;
    /// It scatters about microfacet normals drawn by the pipeline's `MICROFACET_SAMPLING`
    /// (`--microfacet-sampling`).
    const MICROFACETS: bool = false;
    /// It may transmit (refract into the surface): the kernel's two-sided handling of
    /// directions (ray offsets, next event estimation behind the surface, roulette's eta²)
    /// compiles in where a scene has it.
    const TRANSMITS: bool = false;
    /// It scatters on both sides by its nature, as Mitsuba's dielectrics: a material of it is
    /// two-sided whatever a Mitsuba file wraps it in (TOML's `two_sided = false` is refused).
    const BOTH_SIDES: bool = false;
    /// Whether a material of it transmits depends on its parameters (principled's
    /// `spec_trans`): one that does (`transmits`) is treated as a kind with `TRANSMITS` and
    /// `BOTH_SIDES`; the kernel's two-sided handling compiles in by the override
    /// `<STEM>_TRANSMITS` where some material of the scene does, and the kind's WGSL file has
    /// `<stem>_transmits(b: Bsdf) -> bool`, whether material b does.
    const TRANSMITS_BY_PARAMETERS: bool = false;
    /// The slots of its parameter block (0, 1, 2: `p0`..`p2`) whose colour (`xyz`) may be a
    /// texture reference (`textures::Texture`, packed by `pack`): the kernel looks them up at
    /// the hit before the kind's code runs.
    const TEXTURE_SLOTS: &'static [usize] = &[];
    /// The scalar parameters (slot, component: 0..3 for x..w) that may be a texture reference
    /// (a roughness), read as Mitsuba's `eval_1` (`Texture::scalar`); resolved with the colour
    /// slots.
    const SCALAR_TEXTURE_SLOTS: &'static [(usize, usize)] = &[];

    /// Its parameters from a TOML material's fields, each checked (errors go to `f`).
    fn from_fields(f: &mut Fields) -> Self;
    /// A Mitsuba plugin's properties as the fields of a TOML material; `None` when an error was
    /// reported.
    fn from_mitsuba(p: &mut dyn PluginProps) -> Option<Vec<(&'static str, toml::Value)>>;
    /// Its lines of the scene hash, each `(field, value)`.
    fn hash_lines(&self, line: &mut dyn FnMut(&str, String));
    /// Its parameter block, its further numbers (tables) appended to `data`.
    fn pack(&self, data: &mut BsdfData) -> BsdfParams;
    /// Its parameters' textures.
    fn textures(&self) -> Vec<&Texture> {
        Vec::new()
    }
    /// Whether this material transmits: `TRANSMITS`, or by its parameters where
    /// `TRANSMITS_BY_PARAMETERS`.
    fn transmits(&self) -> bool {
        Self::TRANSMITS
    }
    /// Whether a material of the fields `from_mitsuba` gave transmits (as `transmits` of the
    /// material they make).
    fn fields_transmit(_fields: &[(&str, toml::Value)]) -> bool {
        Self::TRANSMITS
    }
    /// Some parameter is a texture, read at the hit's uv parametrisation: the kernel then
    /// computes uvs and resolves textured slots (`SceneFeatures::has_uvs`).
    fn reads_uv(&self) -> bool {
        !self.textures().is_empty()
    }
}

/// The fields of one TOML material's BSDF, read by its kind's `from_fields`: each getter takes
/// its field and checks it (errors name the material's field); fields no getter may take are
/// refused before (`read`).
pub(crate) struct Fields<'c, 'a> {
    ck: &'c mut Checker<'a>,
    material: &'c str,
    span: Range<usize>,
    params: &'c [(String, Spanned<toml::Value>)],
}

impl<'c, 'a> Fields<'c, 'a> {
    pub(super) fn new(ck: &'c mut Checker<'a>, material: &'c str, span: Range<usize>, params: &'c [(String, Spanned<toml::Value>)]) -> Self {
        Fields { ck, material, span, params }
    }

    /// The dotted name of field `f` (`materials.gold.eta`).
    pub fn field(&self, f: &str) -> String {
        format!("materials.{}.{f}", self.material)
    }

    /// Where the material is defined (for a missing field).
    pub fn span(&self) -> Range<usize> {
        self.span.clone()
    }

    fn raw(&self, name: &str) -> Option<&Spanned<toml::Value>> {
        self.params.iter().find(|(k, _)| k == name).map(|(_, v)| v)
    }

    /// Field `name` as a `T`, or an error naming it and what it should be.
    fn typed<T: serde::de::DeserializeOwned>(&mut self, name: &str, expected: &str) -> Option<Spanned<T>> {
        let v = self.raw(name)?.clone();
        match T::deserialize(v.get_ref().clone()) {
            Ok(t) => Some(Spanned::new(v.span(), t)),
            Err(_) => {
                let field = self.field(name);
                self.ck.error(v.span(), field, format!("`{name}` must be {expected} (got {})", v.get_ref()));
                None
            }
        }
    }

    /// Whether field `name` is a table (a texture).
    pub fn is_table(&self, name: &str) -> bool {
        self.raw(name).is_some_and(|v| v.get_ref().is_table())
    }

    /// Where field `name` is written (the material's span where it is not).
    pub fn span_of(&self, name: &str) -> Range<usize> {
        self.raw(name).map_or_else(|| self.span(), |v| v.span())
    }

    /// Whether the material gives field `name`.
    pub fn has(&self, name: &str) -> bool {
        self.raw(name).is_some()
    }

    /// A colour (finite, non-negative channels), or `default` when not given.
    pub fn color(&mut self, name: &str, default: DVec3) -> DVec3 {
        match self.typed::<RawColor>(name, "a number or an array of 3 numbers [r, g, b]") {
            Some(c) => {
                let field = self.field(name);
                self.ck.color(Some(&c), &field)
            }
            None => default,
        }
    }

    /// A finite number with its span, or `None` when not given (or not a number).
    pub fn number(&mut self, name: &str) -> Option<Spanned<f64>> {
        let v = self.typed::<f64>(name, "a number")?;
        let field = self.field(name);
        let checked = self.ck.number(&v, &field);
        v.get_ref().is_finite().then(|| Spanned::new(v.span(), checked))
    }

    /// A colour or a texture (an inline table, `textures::Texture::from_toml`): the colour (a
    /// texture's mean) and the texture.
    pub fn color_or_texture(&mut self, name: &str, default: DVec3) -> (DVec3, Option<Texture>) {
        let Some(v) = self.raw(name).cloned() else { return (default, None) };
        let toml::Value::Table(table) = v.get_ref() else { return (self.color(name, default), None) };
        let mut errors = Vec::new();
        let base = self.ck.file.parent().map(std::path::Path::to_path_buf).unwrap_or_default();
        let texture = Texture::from_toml(table, v.span(), &base, &mut errors);
        for (span, message) in errors {
            self.error(span, name, message);
        }
        (texture.as_ref().map_or(default, Texture::mean), texture)
    }

    /// A boolean, or `default` when not given (or not a boolean).
    pub fn boolean(&mut self, name: &str, default: bool) -> bool {
        self.typed::<bool>(name, "true or false").map_or(default, |b| *b.get_ref())
    }

    /// A finite number (`Ok`) or a string (`Err`, a name such as a material's) with its span,
    /// or `None` when not given (or neither).
    pub fn number_or_string(&mut self, name: &str) -> Option<Spanned<Result<f64, String>>> {
        let v = self.raw(name)?.clone();
        match v.get_ref() {
            toml::Value::String(s) => Some(Spanned::new(v.span(), Err(s.clone()))),
            _ => self.number(name).map(|n| Spanned::new(n.span(), Ok(*n.get_ref()))),
        }
    }

    /// A string with its span, or `None` when not given (or not a string).
    pub fn string(&mut self, name: &str) -> Option<Spanned<String>> {
        self.typed::<String>(name, "a string")
    }

    pub fn error(&mut self, span: Range<usize>, name: &str, message: impl Into<String>) {
        let field = self.field(name);
        self.ck.error(span, field, message);
    }

    pub fn warn(&mut self, span: Range<usize>, name: &str, message: impl Into<String>) {
        let field = self.field(name);
        self.ck.warn(span, field, message);
    }

    /// A warning about the material as a whole.
    pub fn warn_material(&mut self, message: impl Into<String>) {
        let field = format!("materials.{}", self.material);
        self.ck.warn(self.span.clone(), field, message);
    }
}

/// A plugin's properties as a scene format gives them (Mitsuba's XML, `scene::mitsuba`), for a
/// kind's `from_mitsuba`. Each getter takes its property and reports a value of the wrong type
/// itself; what no getter took is refused by `finish`. Positions are byte offsets in the
/// format's sources.
pub(crate) trait PluginProps {
    /// The plugin's name (`roughconductor`).
    fn plugin(&self) -> &str;
    /// Where the plugin's object starts.
    fn at(&self) -> usize;
    /// Where the first nested texture not taken by `color_or_texture` is, if any.
    fn texture(&self) -> Option<usize>;
    /// Whether a nested texture gives property `name`.
    fn has_texture(&self, name: &str) -> bool;
    /// Whether property `name` is given (and not yet taken), as a value or a nested texture.
    fn has(&self, name: &str) -> bool;
    fn color(&mut self, name: &str) -> Option<[f64; 3]>;
    /// A colour without the [0, 1] bound of a reflectance (a conductor's `eta`, `k`): Mitsuba's
    /// `get_unbounded_texture`, which converts a spectrum differently.
    fn unbounded_color(&mut self, name: &str) -> Option<[f64; 3]>;
    /// A colour, or a nested `<texture name=…>` as its TOML inline table (refused with the
    /// reason where pathlab lacks its kind or a parameter).
    fn color_or_texture(&mut self, name: &str) -> Option<toml::Value>;
    /// A float and where its value is.
    fn float(&mut self, name: &str) -> Option<(f64, usize)>;
    fn string(&mut self, name: &str) -> Option<(String, usize)>;
    fn boolean(&mut self, name: &str) -> Option<(bool, usize)>;
    /// A `<float>` (`Ok`) or a `<string>` (`Err`, a name such as a material's) and where its
    /// value is.
    fn float_or_string(&mut self, name: &str) -> Option<(Result<f64, String>, usize)>;
    /// Takes property `name` whatever its type, giving where it is.
    fn take(&mut self, name: &str) -> Option<usize>;
    fn error(&mut self, at: usize, name: &str, message: String);
    fn warn(&mut self, at: usize, name: &str, message: String);
    /// Refuses every property not taken, saying the plugin reads `reads`.
    fn finish(&mut self, reads: &str);
}

/// A colour as a TOML field's value: one number when the channels agree (`RawColor`'s form).
pub(crate) fn color_value(c: [f64; 3]) -> toml::Value {
    toml::Value::try_from(RawColor(c)).expect("a colour is a TOML value")
}
