//! Sampling methods: which sampler, BSDF sampling and light sampling a pipeline uses, and the
//! named presets of the study. Each choice is a WGSL `override` constant (see `gpu::pipeline`);
//! its values are generated into the WGSL from these enums (`shaders::generated_constants`).

use std::fmt;

use crate::names::{named_enum, Named, UnknownName};

named_enum! {
    /// Where the random numbers come from (`shaders/sampler.wgsl`).
    pub enum Sampler("sampler") {
        /// Counter-based hash of (pixel, sample index, dimension).
        Independent = "independent",
        /// The study's Halton: radical inverses with a per-pixel Cranley-Patterson rotation.
        Halton = "halton",
        /// Halton with Owen-scrambled digits per pixel and dimension (pbrt-v4).
        HaltonScrambled = "halton-scrambled",
        /// Owen-scrambled Sobol' (Burley 2020), dimensions padded in shuffled pairs.
        Sobol = "sobol",
    }
}

named_enum! {
    /// How scattering directions are sampled (`shaders/bsdf.wgsl`).
    pub enum BsdfSampling("BSDF sampling") {
        /// Uniform over the sphere (the study's plain method): half the samples are wasted.
        UniformSphere = "uniform-sphere",
        /// Uniform over the hemisphere of the shading normal.
        UniformHemisphere = "uniform-hemisphere",
        /// Cosine-weighted hemisphere.
        Cosine = "cosine",
        /// One-sample mixture of the cosine lobe and the Phong lobe, picked by luminance.
        Phong = "phong",
        /// BIASED, for demonstration: only the Phong lobe is sampled while diffuse + specular
        /// is evaluated (the study's darker specular result).
        PhongLobeOnly = "phong-lobe-only",
    }
}

named_enum! {
    /// How light sources are sampled (`shaders/integrator.wgsl`).
    pub enum LightSampling("light sampling") {
        /// Emission is found only by BSDF-sampled rays.
        None = "none",
        /// Next event estimation: one shadow ray to each spherical light at every vertex.
        Nee = "nee",
        /// NEE and BSDF sampling combined with the power heuristic (beta = 2).
        Mis = "mis",
        /// NEE and BSDF sampling combined with the balance heuristic.
        MisBalance = "mis-balance",
        /// BIASED, for demonstration: NEE plus the full emission of lights hit by BSDF-sampled
        /// rays, counting direct light twice (the study's extra reflections).
        NeeDoubleCount = "nee-double-count",
    }
}

named_enum! {
    /// Which lights next event estimation samples at a vertex (`shaders/light_table.wgsl`).
    pub enum LightSelect("light selection") {
        /// One shadow ray to every light (the default for scenes whose lights are spheres).
        All = "all",
        /// One light, each with probability 1/N.
        Uniform = "uniform",
        /// One light, in proportion to its emitted power (alias table; the default for scenes
        /// with emissive meshes).
        Power = "power",
    }
}

named_enum! {
    /// How a point or direction towards a triangle light is sampled (`shaders/lights.wgsl`).
    pub enum TriangleSampling("triangle sampling") {
        /// Uniform by area, converted to solid angle (Mitsuba's choice).
        Area = "area",
        /// Uniform in the solid angle the triangle subtends (Arvo 1995), by area where that
        /// angle is below 2e-2 sr or above 6.22 sr (f32 loses Arvo's accuracy below).
        SolidAngle = "solid-angle",
    }
}

named_enum! {
    /// How a layered BSDF (Mitsuba's plastic: a dielectric coating over a diffuse base) picks
    /// the lobe it samples (`shaders/bsdf.wgsl`, `LOBE_SELECTION`), whatever the BSDF strategy:
    /// the coating's delta lobe is found only by its own choice.
    pub enum LobeSelection("lobe selection") {
        /// Mitsuba's: the albedos' weight w = mean(specular) / (mean(diffuse) + mean(specular))
        /// times the coating's Fresnel reflectance F at the incident direction, p = F w / (F w
        /// + (1 - F)(1 - w)).
        Fresnel = "fresnel",
        /// The albedos' weight w alone, the same at every incidence.
        Fixed = "fixed",
    }
}

named_enum! {
    /// How next event estimation draws a direction towards an environment map (`+env`;
    /// `shaders/emitters/environment.wgsl`, `ENV_SAMPLING`). A constant environment is always
    /// sampled uniformly.
    pub enum EnvSampling("environment sampling") {
        /// In proportion to the map's luminance times sin(theta): a piecewise-constant
        /// distribution over its texels (Mitsuba's default strategy).
        Luminance = "env-luminance",
        /// Uniform over the sphere of directions.
        Uniform = "env-uniform",
        /// MIS compensation (Karlík et al. 2019, pbrt-v4): in proportion to the luminance less
        /// its mean over the sphere, clamped at zero, times sin(theta). Directions no brighter
        /// than the mean are left to BSDF sampling: methods without MIS cannot use it.
        Compensated = "env-compensated",
    }
}

named_enum! {
    /// How a rough conductor's microfacet normals are sampled (`shaders/microfacet.wgsl`), where
    /// the BSDF strategy samples the material (`phong`): its counterpart of the Phong mixture.
    pub enum MicrofacetSampling("microfacet sampling") {
        /// The distribution of normals, D(m) cos(theta_m) (Walter et al. 2007).
        Ndf = "ndf",
        /// The normals visible from the incident direction (Heitz 2018; Mitsuba's default).
        Vndf = "vndf",
    }
}

named_enum! {
    /// What a researcher's own WGSL technique replaces (`--technique KIND:FILE.wgsl`; the
    /// contract is in `shaders/technique.wgsl`).
    pub enum TechniqueKind("technique kind") {
        /// Sampling a direction at a Phong material (in place of its own strategy).
        Bsdf = "bsdf",
        /// Sampling a point on a spherical light seen from outside it (in place of the cone).
        Light = "light",
        /// Sampling a direction towards the environment map (in place of its luminance
        /// distribution), where next event estimation samples the environment.
        Env = "env",
    }
}

/// The longest technique name (a file stem).
pub const TECHNIQUE_NAME_MAX: usize = 40;

/// A technique's name, its file's stem: ASCII letters, digits, `_` and `-`, at most
/// `TECHNIQUE_NAME_MAX` bytes. Held inline so that a `Method` stays `Copy`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TechniqueName {
    len: u8,
    bytes: [u8; TECHNIQUE_NAME_MAX],
}

/// Why a string cannot be a technique's name.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{0}` cannot name a technique: a technique is named by its file's stem, which must be 1 to 40 ASCII letters, digits, `_` or `-`")]
pub struct BadTechniqueName(pub String);

impl TechniqueName {
    pub fn new(name: &str) -> Result<TechniqueName, BadTechniqueName> {
        let ok = !name.is_empty() && name.len() <= TECHNIQUE_NAME_MAX && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
        if !ok {
            return Err(BadTechniqueName(name.to_string()));
        }
        let mut bytes = [0u8; TECHNIQUE_NAME_MAX];
        bytes[..name.len()].copy_from_slice(name.as_bytes());
        Ok(TechniqueName { len: name.len() as u8, bytes })
    }

    pub fn as_str(&self) -> &str {
        std::str::from_utf8(&self.bytes[..self.len as usize]).expect("checked ASCII")
    }
}

impl fmt::Display for TechniqueName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl fmt::Debug for TechniqueName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

named_enum! {
    /// The named methods of the study.
    pub enum Preset("method") {
        /// Independent samples, uniform sphere sampling, no light sampling (the study's plain).
        Plain = "plain",
        /// The study's Halton sampler, otherwise plain.
        Halton = "halton",
        /// Cosine-weighted hemisphere sampling.
        Cosine = "cosine",
        /// Sampling the Phong BRDF (cosine and Phong lobes).
        Phong = "phong",
        /// Next event estimation, uniform sphere sampling.
        Nee = "nee",
        /// Phong sampling and NEE combined by the power heuristic.
        Mis = "mis",
        /// mis with Owen-scrambled Sobol' samples.
        Best = "best",
    }
}

/// A complete sampling method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Method {
    pub sampler: Sampler,
    pub bsdf: BsdfSampling,
    pub lights: LightSampling,
    /// Light selection; `None`: the scene's default (`Scene::default_light_select`).
    pub select: Option<LightSelect>,
    pub triangles: TriangleSampling,
    pub microfacet: MicrofacetSampling,
    /// How layered BSDFs (plastic) pick their lobe.
    pub lobes: LobeSelection,
    /// Whether next event estimation samples the constant environment as a light (then
    /// escaped rays take the MIS weight against it); off by default, as Mitsuba's `path`
    /// would not leave it, but as pathlab's images were before the environment was a light.
    pub environment: bool,
    /// How the environment is sampled where it is an image and `environment` is on.
    pub env_sampling: EnvSampling,
    /// A researcher's technique sampling Phong materials (`+bsdf=NAME`), in place of their own
    /// strategy, whatever `bsdf` says for the other kinds.
    pub bsdf_technique: Option<TechniqueName>,
    /// A researcher's technique sampling spherical lights from outside (`+light=NAME`).
    pub light_technique: Option<TechniqueName>,
    /// A researcher's technique sampling the environment map (`+env=NAME`, which samples the
    /// environment: `environment` is then true).
    pub env_technique: Option<TechniqueName>,
}

/// The method-name suffix (`mis+env`) of `Method::environment`.
pub const ENVIRONMENT_OPTION: &str = "env";

impl Preset {
    pub const fn method(self) -> Method {
        use BsdfSampling as B;
        use LightSampling as L;
        use Sampler as S;
        let (sampler, bsdf, lights) = match self {
            Preset::Plain => (S::Independent, B::UniformSphere, L::None),
            Preset::Halton => (S::Halton, B::UniformSphere, L::None),
            Preset::Cosine => (S::Independent, B::Cosine, L::None),
            Preset::Phong => (S::Independent, B::Phong, L::None),
            Preset::Nee => (S::Independent, B::UniformSphere, L::Nee),
            Preset::Mis => (S::Independent, B::Phong, L::Mis),
            Preset::Best => (S::Sobol, B::Phong, L::Mis),
        };
        Method {
            sampler,
            bsdf,
            lights,
            select: None,
            triangles: TriangleSampling::Area,
            microfacet: MicrofacetSampling::Vndf,
            lobes: LobeSelection::Fresnel,
            environment: false,
            env_sampling: EnvSampling::Luminance,
            bsdf_technique: None,
            light_technique: None,
            env_technique: None,
        }
    }
}

impl BsdfSampling {
    /// True for the deliberately biased demonstration strategy.
    pub fn is_biased(self) -> bool {
        self == BsdfSampling::PhongLobeOnly
    }
}

impl LightSampling {
    /// True for the deliberately biased demonstration strategy.
    pub fn is_biased(self) -> bool {
        self == LightSampling::NeeDoubleCount
    }
}

/// `sampler=… bsdf=… lights=…`, then `select=…` and `triangles=…` where not the defaults.
impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "sampler={} bsdf={} lights={}", self.sampler, self.bsdf, self.lights)?;
        if let Some(select) = self.select {
            write!(f, " select={select}")?;
        }
        if self.triangles != TriangleSampling::Area {
            write!(f, " triangles={}", self.triangles)?;
        }
        if self.microfacet != MicrofacetSampling::Vndf {
            write!(f, " microfacet={}", self.microfacet)?;
        }
        if self.lobes != LobeSelection::Fresnel {
            write!(f, " lobes={}", self.lobes)?;
        }
        for (kind, name) in self.techniques() {
            write!(f, " technique={kind}:{name}")?;
        }
        Ok(())
    }
}

/// The study's two mistakes, kept as named methods so users can see what bias looks like:
/// `phong-lobe-only` (the `phong` preset sampling only the Phong lobe, without light sampling
/// as in the study; with MIS the light strategy would cover what the lobe misses) and
/// `nee-double-count` (the `nee` preset counting direct light twice).
pub fn biased_demonstrations() -> [(&'static str, Method); 2] {
    [
        ("phong-lobe-only", Method { bsdf: BsdfSampling::PhongLobeOnly, ..Preset::Phong.method() }),
        ("nee-double-count", Method { lights: LightSampling::NeeDoubleCount, ..Preset::Nee.method() }),
    ]
}

/// Named methods that are not presets of the study: `mis-balance`, `mis` with the balance
/// heuristic (the second MIS heuristic of Veach's comparison).
pub fn named_variants() -> [(&'static str, Method); 1] {
    [("mis-balance", Method { lights: LightSampling::MisBalance, ..Preset::Mis.method() })]
}

/// Parts of a method given one by one (the CLI's `--sampler`, `--bsdf`, `--lights`,
/// `--light-select`, `--triangle-sampling`, `--microfacet-sampling`, `--lobe-selection`;
/// Python's keywords), each
/// replacing that part of a named method (`Method::from_name`, the one parser of method names
/// for every front-end).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MethodParts {
    pub sampler: Option<Sampler>,
    pub bsdf: Option<BsdfSampling>,
    pub lights: Option<LightSampling>,
    pub select: Option<LightSelect>,
    pub triangles: Option<TriangleSampling>,
    pub microfacet: Option<MicrofacetSampling>,
    pub lobes: Option<LobeSelection>,
    pub environment: Option<bool>,
    pub env_sampling: Option<EnvSampling>,
    pub bsdf_technique: Option<TechniqueName>,
    pub light_technique: Option<TechniqueName>,
    pub env_technique: Option<TechniqueName>,
}

impl MethodParts {
    /// `method` with the given parts replaced.
    pub fn apply(&self, method: Method) -> Method {
        Method {
            sampler: self.sampler.unwrap_or(method.sampler),
            bsdf: self.bsdf.unwrap_or(method.bsdf),
            lights: self.lights.unwrap_or(method.lights),
            select: self.select.or(method.select),
            triangles: self.triangles.unwrap_or(method.triangles),
            microfacet: self.microfacet.unwrap_or(method.microfacet),
            lobes: self.lobes.unwrap_or(method.lobes),
            environment: self.environment.unwrap_or(method.environment),
            env_sampling: self.env_sampling.unwrap_or(method.env_sampling),
            bsdf_technique: self.bsdf_technique.or(method.bsdf_technique),
            light_technique: self.light_technique.or(method.light_technique),
            env_technique: self.env_technique.or(method.env_technique),
        }
    }
}

impl Method {
    /// True when a deliberately biased demonstration strategy is part of the method.
    pub fn is_biased(&self) -> bool {
        self.bsdf.is_biased() || self.lights.is_biased()
    }

    /// Whether next event estimation samples an environment map by a pdf that is zero where
    /// the map is not black (compensated sampling) while BSDF-sampled rays escaping to it do
    /// not make up for that under MIS: the estimate would be biased.
    pub fn env_pdf_is_incomplete(&self) -> bool {
        self.environment
            && self.env_technique.is_none()
            && self.env_sampling == EnvSampling::Compensated
            && !matches!(self.lights, LightSampling::Mis | LightSampling::MisBalance)
    }

    /// The researcher's techniques the method uses, by kind.
    pub fn techniques(&self) -> impl Iterator<Item = (TechniqueKind, TechniqueName)> {
        [(TechniqueKind::Bsdf, self.bsdf_technique), (TechniqueKind::Light, self.light_technique), (TechniqueKind::Env, self.env_technique)]
            .into_iter()
            .filter_map(|(k, n)| n.map(|n| (k, n)))
    }

    /// The same method using technique `name` of `kind`.
    pub fn with_technique(self, kind: TechniqueKind, name: TechniqueName) -> Method {
        match kind {
            TechniqueKind::Bsdf => Method { bsdf_technique: Some(name), ..self },
            TechniqueKind::Light => Method { light_technique: Some(name), ..self },
            // An environment technique runs where next event estimation samples the environment.
            TechniqueKind::Env => Method { env_technique: Some(name), environment: true, ..self },
        }
    }

    /// The preset with exactly these settings, if any.
    pub fn preset(&self) -> Option<Preset> {
        Preset::ALL.into_iter().find(|p| p.method() == *self)
    }

    /// The same method with the light options of the defaults (no `+…` suffix).
    fn base(&self) -> Method {
        Method {
            select: None,
            triangles: TriangleSampling::Area,
            microfacet: MicrofacetSampling::Vndf,
            lobes: LobeSelection::Fresnel,
            environment: false,
            env_sampling: EnvSampling::Luminance,
            bsdf_technique: None,
            light_technique: None,
            env_technique: None,
            ..*self
        }
    }

    /// The one name a method is shown and recorded under (the inverse of `from_name`): its
    /// preset's, a biased demonstration's, or its parts `sampler/bsdf/lights`; then `+SELECT`
    /// for a light selection given explicitly, `+solid-angle` for spherical-triangle
    /// sampling, `+ndf` for microfacet sampling of the distribution, `+fixed` for layered
    /// BSDFs' fixed lobe selection and `+env` for a sampled environment (e.g.
    /// `mis+power+solid-angle`).
    pub fn name(&self) -> String {
        let base = self.base();
        let mut name = if let Some(p) = base.preset() {
            p.name().to_string()
        } else if let Some((name, _)) = named_variants().into_iter().chain(biased_demonstrations()).find(|(_, m)| *m == base) {
            name.to_string()
        } else {
            format!("{}/{}/{}", self.sampler, self.bsdf, self.lights)
        };
        if let Some(select) = self.select {
            name = format!("{name}+{select}");
        }
        if self.triangles != TriangleSampling::Area {
            name = format!("{name}+{}", self.triangles);
        }
        if self.microfacet != MicrofacetSampling::Vndf {
            name = format!("{name}+{}", self.microfacet);
        }
        if self.lobes != LobeSelection::Fresnel {
            name = format!("{name}+{}", self.lobes);
        }
        // (`+env=NAME` says `+env` too.)
        if self.environment && self.env_technique.is_none() {
            name = format!("{name}+{ENVIRONMENT_OPTION}");
        }
        if self.env_sampling != EnvSampling::Luminance {
            name = format!("{name}+{}", self.env_sampling);
        }
        for (kind, technique) in self.techniques() {
            name = format!("{name}+{kind}={technique}");
        }
        name
    }

    /// A name made by `name`: a base method, then `+` light options.
    pub fn from_name(name: &str) -> Result<Method, UnknownName> {
        let mut parts = name.split('+');
        let mut method = Method::base_from_name(parts.next().unwrap_or(""))?;
        for option in parts {
            if let Some(select) = LightSelect::from_name(option) {
                method.select = Some(select);
            } else if let Some(t) = TriangleSampling::from_name(option) {
                method.triangles = t;
            } else if let Some(m) = MicrofacetSampling::from_name(option) {
                method.microfacet = m;
            } else if let Some(l) = LobeSelection::from_name(option) {
                method.lobes = l;
            } else if option == ENVIRONMENT_OPTION {
                method.environment = true;
            } else if let Some(e) = EnvSampling::from_name(option) {
                method.env_sampling = e;
            } else if let Some((kind, technique)) = option.split_once('=').and_then(|(k, n)| Some((TechniqueKind::from_name(k)?, n))) {
                let technique = TechniqueName::new(technique).map_err(|e| UnknownName { what: "technique", name: technique.to_string(), known: e.to_string() })?;
                method = method.with_technique(kind, technique);
            } else {
                let known: Vec<&str> = LightSelect::names()
                    .into_iter()
                    .chain(TriangleSampling::names())
                    .chain(MicrofacetSampling::names())
                    .chain(LobeSelection::names())
                    .chain([ENVIRONMENT_OPTION])
                    .chain(EnvSampling::names())
                    .chain(["bsdf=NAME", "light=NAME", "env=NAME"])
                    .collect();
                return Err(UnknownName { what: "light option", name: option.to_string(), known: known.join(", ") });
            }
        }
        Ok(method)
    }

    /// A preset, a biased demonstration or `sampler/bsdf/lights` by name.
    fn base_from_name(name: &str) -> Result<Method, UnknownName> {
        if let Some(p) = Preset::from_name(name) {
            return Ok(p.method());
        }
        if let Some((_, m)) = named_variants().into_iter().chain(biased_demonstrations()).find(|(n, _)| *n == name) {
            return Ok(m);
        }
        let unknown = || UnknownName { what: "method", name: name.to_string(), known: method_names().join(", ") };
        let mut parts = name.split('/');
        match (parts.next(), parts.next(), parts.next(), parts.next()) {
            (Some(s), Some(b), Some(l), None) => Ok(Method {
                sampler: s.parse()?,
                bsdf: b.parse()?,
                lights: l.parse()?,
                select: None,
                triangles: TriangleSampling::Area,
                microfacet: MicrofacetSampling::Vndf,
                lobes: LobeSelection::Fresnel,
                environment: false,
                env_sampling: EnvSampling::Luminance,
                bsdf_technique: None,
                light_technique: None,
                env_technique: None,
            }),
            _ => Err(unknown()),
        }
    }
}

/// Every named method (presets, named variants, then the biased demonstrations).
pub fn method_names() -> Vec<&'static str> {
    Preset::ALL.iter().map(|p| p.name()).chain(named_variants().map(|(n, _)| n)).chain(biased_demonstrations().map(|(n, _)| n)).collect()
}

impl serde::Serialize for Method {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}

impl<'de> serde::Deserialize<'de> for Method {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = <String as serde::Deserialize>::deserialize(d)?;
        Method::from_name(&s).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_name_reads_back_as_the_method() {
        for sampler in Sampler::ALL {
            for bsdf in BsdfSampling::ALL {
                for lights in LightSampling::ALL {
                    for select in [None, Some(LightSelect::All), Some(LightSelect::Uniform), Some(LightSelect::Power)] {
                        for triangles in TriangleSampling::ALL {
                            for microfacet in MicrofacetSampling::ALL {
                                for lobes in LobeSelection::ALL {
                                    for environment in [false, true] {
                                        for env_sampling in EnvSampling::ALL {
                                            let m = Method { sampler, bsdf, lights, select, triangles, microfacet, lobes, environment, env_sampling, bsdf_technique: None, light_technique: None, env_technique: None };
                                            assert_eq!(Method::from_name(&m.name()), Ok(m), "{}", m.name());
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(Method::from_name("best"), Ok(Preset::Best.method()));
        assert!(Method::from_name("fastest").is_err());
        assert!(Method::from_name("sobol/phong").is_err());
        assert_eq!(Method::from_name("mis+power+solid-angle").unwrap().name(), "mis+power+solid-angle");
        assert!(Method::from_name("mis+brightest").is_err());
        assert_eq!(Method::from_name("mis+fixed").unwrap(), Method { lobes: LobeSelection::Fixed, ..Preset::Mis.method() });
        assert_eq!(Method::from_name("best+uniform+env").unwrap(), Method { select: Some(LightSelect::Uniform), environment: true, ..Preset::Best.method() });
        let cone = TechniqueName::new("my_cone").unwrap();
        let with = Method::from_name("mis+light=my_cone").unwrap();
        assert_eq!(with, Method { light_technique: Some(cone), ..Preset::Mis.method() });
        assert_eq!(with.name(), "mis+light=my_cone");
        let both = Method::from_name("sobol/cosine/mis+bsdf=phong-lobe+light=my_cone").unwrap();
        assert_eq!(Method::from_name(&both.name()), Ok(both));
        assert!(Method::from_name("mis+light=my cone").is_err());
        assert!(Method::from_name("mis+lens=x").is_err());
        let sky = Method::from_name("mis+env=my_sky").unwrap();
        assert!(sky.environment && sky.env_technique == Some(TechniqueName::new("my_sky").unwrap()));
        assert_eq!(sky.name(), "mis+env=my_sky");
    }

    #[test]
    fn names_are_those_of_the_command_line() {
        assert_eq!(Sampler::HaltonScrambled.name(), "halton-scrambled");
        assert_eq!("nee-double-count".parse::<LightSampling>(), Ok(LightSampling::NeeDoubleCount));
        assert!("phong".parse::<Sampler>().is_err());
        assert_eq!(crate::names::wgsl_constants::<Sampler>("SAMPLER").lines().nth(2), Some("const SAMPLER_HALTON_SCRAMBLED: u32 = 2u;"));
    }
}
