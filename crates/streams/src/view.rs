//! What the streams stage reads of the scene.

karst_scene::view! {
    /// The streams stage's view of the scene: the terrain over the domain the water runs on,
    /// the springs, their total discharge (m³/s, `hydro.total_discharge`) and its parameters.
    pub struct StreamsView<'s> {
        domain: Domain,
        terrain: Terrain,
        keypoints: Keypoints,
        total_discharge: TotalDischarge,
        streams: Streams,
    }
}
