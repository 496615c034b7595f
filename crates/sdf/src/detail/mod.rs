//! What `[sdf] passage_detail = "full"` adds to the passages (docs/sdf.md): rough walls
//! ([`walls`]), speleothems ([`speleothems`]), breakdown ([`breakdown`]) and sediment floors
//! ([`sediment`]), the last three as rock put back into the void ([`rock`]).
//!
//! In the artifact these are one trailing field of [`crate::SdfModel`], [`FullDetail`], which
//! postcard writes as nothing at all when it is empty (below `full`), so that `off` and
//! `passages` keep their artifacts byte for byte; with `full` it is an option tag and the
//! features.

pub mod breakdown;
pub mod place;
pub mod rock;
pub mod sediment;
pub mod speleothems;
pub mod walls;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use karst_artifact::Invalid;

use rock::Piece;
use walls::Relief;

/// The features of `full` passage detail.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Features {
    pub relief: Relief,
    /// Speleothems and breakdown blocks.
    pub pieces: Vec<Piece>,
}

/// `full` passage detail, or nothing.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FullDetail(pub Option<Features>);

impl FullDetail {
    pub fn validate(&self) -> Result<(), Invalid> {
        let Some(f) = &self.0 else { return Ok(()) };
        f.relief.validate("full.relief")?;
        for (i, p) in f.pieces.iter().enumerate() {
            p.validate(&|| format!("full.pieces[{i}]"))?;
        }
        Ok(())
    }

    pub fn relief(&self) -> Option<&Relief> {
        self.0.as_ref().map(|f| &f.relief)
    }

    pub fn pieces(&self) -> &[Piece] {
        self.0.as_ref().map_or(&[], |f| &f.pieces)
    }
}

/// Readable formats get an option; postcard gets nothing for `None` (a unit is no bytes) and
/// a tagged `Some` otherwise.
impl Serialize for FullDetail {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match (&self.0, s.is_human_readable()) {
            (features, true) => features.serialize(s),
            (None, false) => s.serialize_unit(),
            (Some(features), false) => s.serialize_some(features),
        }
    }
}

/// The payload's last field: when postcard has no byte left for its tag, the artifact was
/// written without `full` detail (an explicit `None` tag is refused: it is never written) (what the artifact reader's check that every byte was read
/// then confirms), and a truncated one fails that check or the envelope's hash.
impl<'de> Deserialize<'de> for FullDetail {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        if d.is_human_readable() {
            return Option::<Features>::deserialize(d).map(FullDetail);
        }
        match Option::<Features>::deserialize(d) {
            Ok(Some(features)) => Ok(FullDetail(Some(features))),
            // A tag for `None` is never written: it is a byte after the payload's fields.
            Ok(None) => Err(serde::de::Error::custom(
                "a byte after the payload's fields (no full detail is written as no byte at all)",
            )),
            Err(_) => Ok(FullDetail(None)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SdfModel;
    use crate::field::carved::CarvedTerrain;
    use crate::synthetic;
    use crate::view::SdfView;
    use karst_scene::{Scene, SceneView};

    /// The synthetic network (flooded phreatic conduits below z = 60, streams and dry ones
    /// above) with full passage detail, and the same without speleothems.
    fn synthetic_full(density: f64) -> SdfModel {
        let text = format!(
            "{}\n[sdf]\npassage_detail = \"full\"\nspeleothem_density = {density}\ndrip_depth = 1000\n",
            synthetic::SCENE
        );
        let scene = Scene::parse(&text, std::path::Path::new("synthetic.toml")).unwrap();
        let (skeleton, hydro) = synthetic::network(3, 24, 8);
        crate::build(&SdfView::of(&scene), &skeleton, &hydro).unwrap()
    }

    #[test]
    fn no_speleothem_grows_in_water() {
        let model = synthetic_full(2.0);
        let flooded: Vec<_> = model.water.iter().filter(|w| w.level.is_none()).collect();
        assert!(!flooded.is_empty() && model.water.iter().any(|w| w.level.is_some()), "both water types");
        let bare = CarvedTerrain::new(SdfModel { full: FullDetail::default(), ..model.clone() });
        let speleothems: Vec<&Piece> = model
            .full
            .pieces()
            .iter()
            .filter(|p| !matches!(p.kind, rock::PieceKind::Block | rock::PieceKind::Sediment))
            .collect();
        assert!(speleothems.len() > 50, "{} speleothems", speleothems.len());
        for piece in speleothems {
            let rock::Shape::Cone { a, b, .. } = piece.shape else { panic!("{piece:?}") };
            let mid = (crate::tree::sweep::to_dvec(a) + crate::tree::sweep::to_dvec(b)) * 0.5;
            // Not in the water of the plain cave (no rock pieces), flooded or stream.
            assert!(bare.water(mid) > 0.0, "{piece:?} is in water ({})", bare.water(mid));
            if let (rock::PieceKind::Stalagmite | rock::PieceKind::Column, rock::Shape::Cone { ra, .. }) =
                (piece.kind, piece.shape)
            {
                // Its foot stands on a dry floor, not in a stream.
                let foot = crate::tree::sweep::to_dvec(a) + glam::DVec3::Z * (ra as f64 + 0.05);
                assert!(bare.water(foot) > 0.0, "{piece:?} stands in water ({})", bare.water(foot));
            }
        }
    }

    #[test]
    fn the_drip_density_scales_the_count_and_the_placement_is_deterministic() {
        let sparse = synthetic_full(0.2);
        let dense = synthetic_full(2.0);
        let count = |m: &SdfModel| m.full.pieces().len();
        assert!(count(&dense) > 3 * count(&sparse), "{} vs {}", count(&dense), count(&sparse));
        assert_eq!(dense, synthetic_full(2.0));
    }
    use crate::detail::rock::{PieceKind, Shape};
    use crate::detail::walls::ReliefNoise;
    use karst_scene::rng::Random;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Payload {
        a: u32,
        full: FullDetail,
    }

    #[test]
    fn empty_detail_is_no_bytes_and_full_detail_round_trips() {
        let empty = Payload { a: 7, full: FullDetail(None) };
        let bytes = postcard::to_stdvec(&empty).unwrap();
        assert_eq!(bytes, postcard::to_stdvec(&7u32).unwrap());
        assert_eq!(postcard::from_bytes::<Payload>(&bytes).unwrap(), empty);
        let relief = Relief {
            fraction: 0.1,
            max: 0.5,
            noise: ReliefNoise::draw(&mut Random::stream(1, "a", "b"), 4.0),
        };
        let piece = Piece {
            kind: PieceKind::Column,
            shape: Shape::Cone { a: [0.0, 0.0, 0.0], ra: 0.3, b: [0.0, 0.0, 2.0], rb: 0.2 },
        };
        let full = Payload { a: 7, full: FullDetail(Some(Features { relief, pieces: vec![piece] })) };
        let bytes = postcard::to_stdvec(&full).unwrap();
        let (back, rest) = postcard::take_from_bytes::<Payload>(&bytes).unwrap();
        assert!(rest.is_empty());
        assert_eq!(back, full);
        let json = serde_json::to_string(&full).unwrap();
        assert_eq!(serde_json::from_str::<Payload>(&json).unwrap(), full);
    }
}
