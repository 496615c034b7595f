//! What the sdf stage reads of the scene.

karst_scene::view! {
    /// The sdf stage's view of the scene: the terrain over the domain it carves, the streams'
    /// parameters (the banks' slope, the sheets' thickness, the mouths' radius), its own, and
    /// the seed of its noise.
    pub struct SdfView<'s> {
        seed: Seed,
        domain: Domain,
        terrain: Terrain,
        streams: Streams,
        sdf: Sdf,
    }
}
