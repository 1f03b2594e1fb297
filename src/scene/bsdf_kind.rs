//! The registry of BSDF kinds: the one list a new kind joins. Each kind is one WGSL file,
//! `shaders/bsdfs/<stem>.wgsl`, with the two entry points the dispatcher calls,
//! `eval_pdf_<stem>_bsdf` and `sample_<stem>_bsdf`; from this list the host generates the
//! kinds' numbers (`BSDF_KIND_*`), one `HAS_<KIND>` override per kind (a pipeline compiles only
//! the kinds its scene uses) and the dispatch (`shaders::bsdf_dispatch`).

crate::names::named_enum! {
    /// The kind of a material's BSDF (`Material::bsdf_kind`).
    pub enum BsdfKind("BSDF kind") {
        /// The normalised modified Phong BRDF (the study's); the kind of every material that is
        /// not a conductor.
        Phong = "phong",
        /// Mitsuba's smooth `conductor`: a mirror with the Fresnel term of a complex index.
        Conductor = "conductor",
        /// Mitsuba's `roughconductor`: Torrance-Sparrow microfacet reflection.
        RoughConductor = "rough-conductor",
    }
}

impl BsdfKind {
    /// The stem of its WGSL file and functions (`rough_conductor`).
    pub fn stem(self) -> &'static str {
        match self {
            BsdfKind::Phong => "phong",
            BsdfKind::Conductor => "conductor",
            BsdfKind::RoughConductor => "rough_conductor",
        }
    }

    /// The pipeline constant that compiles the kind in (`HAS_ROUGH_CONDUCTOR`).
    pub fn has_override(self) -> &'static str {
        match self {
            BsdfKind::Phong => "HAS_PHONG",
            BsdfKind::Conductor => "HAS_CONDUCTOR",
            BsdfKind::RoughConductor => "HAS_ROUGH_CONDUCTOR",
        }
    }

    /// Whether the kind's only lobe is a delta: next event estimation cannot contribute, and
    /// only its own sampling finds its directions.
    pub fn is_delta(self) -> bool {
        matches!(self, BsdfKind::Conductor)
    }

    /// The bit of this kind in a set of kinds (`SceneFeatures::bsdf_kinds`).
    pub fn bit(self) -> u32 {
        1 << self.constant()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_its_own_stem_and_override() {
        for k in BsdfKind::ALL {
            assert_eq!(k.stem(), k.name().replace('-', "_"));
            assert_eq!(k.has_override(), format!("HAS_{}", k.stem().to_uppercase()));
        }
    }
}
