//! What the skeleton stage reads of the scene.

use karst_costgraph::CostgraphView;
use karst_geology::Point;

karst_scene::view! {
    /// The skeleton stage's view of the scene: the bedrock its branches stay in, `[sampling]`
    /// (the radius its derived defaults scale with, docs/skeleton.md), the geology
    /// that classifies and orients its conduits, the key points and connectivity it routes,
    /// the phases, its parameters, the seed, `sdf.passage_detail` (whether conduits get passage
    /// profiles), and `[costgraph]`: the skeleton costs the edges
    /// its searches read under the cost graph's model ([`SkeletonView::costs`]).
    pub struct SkeletonView<'s> {
        seed: Seed,
        domain: Domain,
        terrain: Terrain,
        geology: Geology,
        keypoints: Keypoints,
        connectivity: Connectivity,
        phases: Phases,
        costgraph: Costgraph,
        sampling: Sampling,
        skeleton: Skeleton,
        passage_detail: PassageDetail,
    }
}

impl<'s> SkeletonView<'s> {
    /// Whether `p` is in the bedrock: inside the domain, below the ground.
    pub fn in_bedrock(&self, p: Point) -> bool {
        self.terrain.in_bedrock(self.domain, p)
    }

    /// The cost graph stage's sections, which this view holds too: what the cost model of
    /// the edges is made of.
    pub fn costs(&self) -> CostgraphView<'s> {
        CostgraphView {
            domain: self.domain,
            terrain: self.terrain,
            geology: self.geology,
            keypoints: self.keypoints,
            connectivity: self.connectivity,
            costgraph: self.costgraph,
            forced_links: &self.skeleton.forced_links,
            budget: self.budget,
            output_budget: self.output_budget,
            frame: self.frame,
        }
    }
}
