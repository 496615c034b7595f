//! What the export stage reads of the scene.

karst_scene::view! {
    /// The export stage's view of the scene: the geology (the rock layer of each sample in the
    /// GOCAD VSet), the domain, terrain and key points (the GIS formats' grid, ground and
    /// points), the formats to write, and the frame (the origin the exports add back).
    pub struct ExportView<'s> {
        domain: Domain,
        terrain: Terrain,
        geology: Geology,
        keypoints: Keypoints,
        export: Export,
    }
}
