//! What the mesher stage reads of the scene.

karst_scene::view! {
    /// The mesher stage's view of the scene: the sinks and springs (the cleanup keeps the air
    /// around them) and its parameters.
    pub struct MesherView<'s> {
        keypoints: Keypoints,
        mesher: Mesher,
    }
}
