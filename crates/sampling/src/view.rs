//! What the sampling stage reads of the scene.

karst_scene::view! {
    /// The sampling stage's view of the scene: the bedrock (domain, terrain, geology) it fills,
    /// the key points it places first, its parameters and the seed of its random streams.
    pub struct SamplingView<'s> {
        seed: Seed,
        domain: Domain,
        terrain: Terrain,
        geology: Geology,
        keypoints: Keypoints,
        sampling: Sampling,
    }
}
