//! What the cost graph stage reads of the scene, and what the cost model is made of.

karst_scene::view! {
    /// The cost graph stage's view of the scene: the domain, terrain, geology and key points the cost
    /// model reads (the terrain orients the assumed joints) ([`crate::CostModel::new`]), the connectivity the graph is checked against, the
    /// stage's parameters and the forced links (whose corridors paris2021 makes cheap).
    ///
    /// The skeleton costs the edges its searches read under the same model: it makes this view
    /// from its own, which holds these sections too, and the graph checks that it was made
    /// under the same ones ([`crate::CostGraph::cost_from`]).
    pub struct CostgraphView<'s> {
        domain: Domain,
        terrain: Terrain,
        geology: Geology,
        keypoints: Keypoints,
        connectivity: Connectivity,
        costgraph: Costgraph,
        forced_links: ForcedLinks,
    }
}
