//! What the metrics stage reads of the scene.

karst_scene::view! {
    /// The metrics stage's view of the scene: no section (the network's statistics come from
    /// the artifacts alone).
    pub struct MetricsView<'s> {}
}
