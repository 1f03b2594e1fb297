//! The numbers materials read beyond their BSDFs' parameter blocks, one array for the scene:
//! roughplastic's coating tables (`bsdfs::rough_plastic`) and textures' records (`textures`).

/// The numbers BSDFs read beyond their parameter blocks, one array for the scene (`bsdf_data`
/// in bsdf.wgsl, bound at `bindings::BSDF_DATA`): roughplastic's transmittance table, textures.
/// A kind appends its own while packing and keeps where they start in its block.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BsdfData(pub Vec<f32>);

impl BsdfData {
    /// Appends `values`; returns the index of the first.
    pub fn push(&mut self, values: &[f32]) -> u32 {
        let first = self.0.len() as u32;
        self.0.extend_from_slice(values);
        first
    }
}

