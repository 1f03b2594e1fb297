//! The numbers materials read beyond their BSDFs' parameter blocks, one array for the scene:
//! roughplastic's coating tables (`bsdfs::rough_plastic`) and textures' records (`textures`).

/// The numbers BSDFs read beyond their parameter blocks, one array for the scene (`bsdf_data`
/// in bsdf.wgsl, bound at `bindings::BSDF_DATA`): roughplastic's transmittance table, textures.
/// A kind appends its own while packing and keeps where they start in its block. The second
/// field names the mesh attributes that `mesh_attribute` textures read, in the order of the
/// kernel's attribute table (`Scene::mesh_attribute_names`, which `pack_materials` starts it
/// with).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BsdfData(pub Vec<f32>, pub Vec<String>);

impl BsdfData {
    /// The slot of mesh attribute `name` in the kernel's attribute table (appended where new).
    pub fn attribute_slot(&mut self, name: &str) -> usize {
        match self.1.iter().position(|n| n == name) {
            Some(i) => i,
            None => {
                self.1.push(name.to_string());
                self.1.len() - 1
            }
        }
    }

    /// Appends `values`; returns the index of the first.
    pub fn push(&mut self, values: &[f32]) -> u32 {
        let first = self.0.len() as u32;
        self.0.extend_from_slice(values);
        first
    }
}

