//! What the microfacet BSDFs share: the distribution of normals (its WGSL in the microfacet
//! shader file).

crate::names::named_enum! {
    /// The microfacet distribution of a rough BSDF (`shaders/microfacet.wgsl`).
    pub enum Distribution("microfacet distribution") {
        /// Beckmann's (Mitsuba's default).
        Beckmann = "beckmann",
        /// Trowbridge-Reitz / GGX: longer tails.
        Ggx = "ggx",
    }
}
