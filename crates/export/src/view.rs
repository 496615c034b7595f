//! What the export stage reads of the scene.

karst_scene::view! {
    /// The export stage's view of the scene: the geology (the rock layer of each sample in the
    /// GOCAD VSet), the formats to write, and the frame (the origin the exports add back).
    pub struct ExportView<'s> {
        geology: Geology,
        export: Export,
    }
}
