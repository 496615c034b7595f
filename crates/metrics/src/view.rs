//! What the metrics stage reads of the scene.

karst_scene::view! {
    /// The metrics stage's view of the scene: the network's statistics come from the artifacts
    /// alone; `[skeleton]` and `[sampling]` give the values the hints cite (`hints.rs`), and
    /// `[calibrate]`'s `like` or `target` the network they are relative to (`aim.rs`).
    pub struct MetricsView<'s> {
        sampling: Sampling,
        skeleton: Skeleton,
        aim: CalibrationAim,
    }
}
