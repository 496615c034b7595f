//! What the hydro stage reads of the scene.

karst_scene::view! {
    /// The hydro stage's view of the scene: the terrain over the domain (catchment recharge),
    /// the sinks and springs, and its parameters.
    pub struct HydroView<'s> {
        domain: Domain,
        terrain: Terrain,
        keypoints: Keypoints,
        hydro: Hydro,
    }
}
