//! Sampling methods: which sampler, BSDF sampling and light sampling a pipeline uses, and the
//! named presets of the study. Each choice is a WGSL `override` constant (see `gpu::pipeline`).

use std::fmt;

use clap::ValueEnum;

/// Where the random numbers come from (`shaders/sampler.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, ValueEnum)]
#[value(rename_all = "kebab-case")]
pub enum Sampler {
    /// Counter-based hash of (pixel, sample index, dimension).
    Independent,
    /// The study's Halton: radical inverses with a per-pixel Cranley-Patterson rotation.
    Halton,
    /// Halton with Owen-scrambled digits per pixel and dimension (pbrt-v4).
    HaltonScrambled,
    /// Owen-scrambled Sobol' (Burley 2020), dimensions padded in shuffled pairs.
    Sobol,
}

/// How scattering directions are sampled (`shaders/bsdf.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, ValueEnum)]
#[value(rename_all = "kebab-case")]
pub enum BsdfSampling {
    /// Uniform over the sphere (the study's plain method): half the samples are wasted.
    UniformSphere,
    /// Uniform over the hemisphere of the shading normal.
    UniformHemisphere,
    /// Cosine-weighted hemisphere.
    Cosine,
    /// One-sample mixture of the cosine lobe and the Phong lobe, picked by luminance.
    Phong,
    /// BIASED, for demonstration: only the Phong lobe is sampled while diffuse + specular is
    /// evaluated (the study's darker specular result).
    PhongLobeOnly,
}

/// How light sources are sampled (`shaders/integrator.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, ValueEnum)]
pub enum LightSampling {
    /// Emission is found only by BSDF-sampled rays.
    None,
    /// Next event estimation: one shadow ray to each spherical light at every vertex.
    Nee,
    /// NEE and BSDF sampling combined with the power heuristic.
    Mis,
    /// BIASED, for demonstration: NEE plus the full emission of lights hit by BSDF-sampled
    /// rays, counting direct light twice (the study's extra reflections).
    NeeDoubleCount,
}

/// The named methods of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, ValueEnum)]
pub enum Preset {
    Plain,
    Halton,
    Cosine,
    Phong,
    Nee,
    Mis,
    Best,
}

/// A complete sampling method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Method {
    pub sampler: Sampler,
    pub bsdf: BsdfSampling,
    pub lights: LightSampling,
}

impl Preset {
    pub const ALL: [Preset; 7] =
        [Preset::Plain, Preset::Halton, Preset::Cosine, Preset::Phong, Preset::Nee, Preset::Mis, Preset::Best];

    pub fn method(self) -> Method {
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
        Method { sampler, bsdf, lights }
    }

    /// The command-line spelling.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Plain => "plain",
            Preset::Halton => "halton",
            Preset::Cosine => "cosine",
            Preset::Phong => "phong",
            Preset::Nee => "nee",
            Preset::Mis => "mis",
            Preset::Best => "best",
        }
    }
}

impl Sampler {
    pub const ALL: [Sampler; 4] = [Sampler::Independent, Sampler::Halton, Sampler::HaltonScrambled, Sampler::Sobol];
    pub fn name(self) -> &'static str {
        match self {
            Sampler::Independent => "independent",
            Sampler::Halton => "halton",
            Sampler::HaltonScrambled => "halton-scrambled",
            Sampler::Sobol => "sobol",
        }
    }
    /// Value of the WGSL constant `SAMPLER`.
    pub fn constant(self) -> u32 {
        self as u32
    }
}

impl BsdfSampling {
    /// Every strategy, the biased demonstration included.
    pub const ALL: [BsdfSampling; 5] = [
        BsdfSampling::UniformSphere,
        BsdfSampling::UniformHemisphere,
        BsdfSampling::Cosine,
        BsdfSampling::Phong,
        BsdfSampling::PhongLobeOnly,
    ];
    /// True for the deliberately biased demonstration strategy.
    pub fn is_biased(self) -> bool {
        self == BsdfSampling::PhongLobeOnly
    }
    pub fn name(self) -> &'static str {
        match self {
            BsdfSampling::UniformSphere => "uniform-sphere",
            BsdfSampling::UniformHemisphere => "uniform-hemisphere",
            BsdfSampling::Cosine => "cosine",
            BsdfSampling::Phong => "phong",
            BsdfSampling::PhongLobeOnly => "phong-lobe-only",
        }
    }
    /// Value of the WGSL constant `BSDF_SAMPLING`.
    pub fn constant(self) -> u32 {
        self as u32
    }
}

impl LightSampling {
    /// Every strategy, the biased demonstration included.
    pub const ALL: [LightSampling; 4] =
        [LightSampling::None, LightSampling::Nee, LightSampling::Mis, LightSampling::NeeDoubleCount];
    /// True for the deliberately biased demonstration strategy.
    pub fn is_biased(self) -> bool {
        self == LightSampling::NeeDoubleCount
    }
    pub fn name(self) -> &'static str {
        match self {
            LightSampling::None => "none",
            LightSampling::Nee => "nee",
            LightSampling::Mis => "mis",
            LightSampling::NeeDoubleCount => "nee-double-count",
        }
    }
    /// Value of the WGSL constant `LIGHT_SAMPLING`.
    pub fn constant(self) -> u32 {
        self as u32
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "sampler={} bsdf={} lights={}",
            self.sampler.name(),
            self.bsdf.name(),
            self.lights.name()
        )
    }
}

impl Method {
    /// True when a deliberately biased demonstration strategy is part of the method.
    pub fn is_biased(&self) -> bool {
        self.bsdf.is_biased() || self.lights.is_biased()
    }

    /// The preset with exactly these settings, if any.
    pub fn preset(&self) -> Option<Preset> {
        Preset::ALL.into_iter().find(|p| p.method() == *self)
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

/// A preset or a biased demonstration by its command-line name.
pub fn method_by_name(name: &str) -> Option<Method> {
    Preset::ALL
        .iter()
        .find(|p| p.name() == name)
        .map(|p| p.method())
        .or_else(|| biased_demonstrations().into_iter().find(|(n, _)| *n == name).map(|(_, m)| m))
}

/// The name a method is shown under (the inverse of `method_by_name` where it has one): its
/// preset's, a biased demonstration's, or its parts.
pub fn method_name(method: &Method) -> String {
    if let Some(p) = method.preset() {
        return p.name().to_string();
    }
    if let Some((name, _)) = biased_demonstrations().into_iter().find(|(_, m)| m == method) {
        return name.to_string();
    }
    format!("{}/{}/{}", method.sampler.name(), method.bsdf.name(), method.lights.name())
}

/// Every name `method_by_name` knows.
pub fn method_names() -> Vec<&'static str> {
    Preset::ALL.iter().map(|p| p.name()).chain(biased_demonstrations().map(|(n, _)| n)).collect()
}
