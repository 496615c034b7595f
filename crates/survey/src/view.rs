//! What the survey stage reads of the scene.

karst_scene::view! {
    /// The survey stage's view of the scene: no section (the stations, their spacing and the
    /// measurement come from the artifacts alone).
    pub struct SurveyView<'s> {}
}
