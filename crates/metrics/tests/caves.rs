//! The two CC0 caves of `fixtures/caves` against karstnet 1.2.5's values
//! (`expected-metrics.json`): every key within 1e-9 relative.

mod common;

use common::{as_map, assert_same, caves_dir, json_map};
use karst_metrics::characterize;
use karst_metrics::readers::{read_karstnet, read_pline};

fn expected(cave: &str) -> std::collections::BTreeMap<String, f64> {
    let text =
        std::fs::read_to_string(caves_dir().join("expected-metrics.json")).expect("expected-metrics.json");
    let all: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    json_map(&all[cave])
}

#[test]
fn sakany_matches_karstnet() {
    let net = read_karstnet(&caves_dir().join("Sakany")).expect("Sakany reads");
    assert_eq!(net.nodes.len(), 1716);
    let m = characterize(&net).expect("Sakany is valid");
    assert_same(&as_map(&m), &expected("Sakany"), 1e-9, &[], "Sakany");
}

#[test]
fn monachou_matches_karstnet() {
    let net = read_pline(&caves_dir().join("Monachou.pl")).expect("Monachou reads");
    let m = characterize(&net).expect("Monachou is valid");
    assert_same(&as_map(&m), &expected("Monachou"), 1e-9, &[], "Monachou");
}

#[test]
fn json_uses_karstnet_key_names() {
    let net = read_pline(&caves_dir().join("Monachou.pl")).expect("Monachou reads");
    let m = characterize(&net).expect("Monachou is valid");
    let ours: serde_json::Value = serde_json::to_value(&m).expect("serialisable");
    let keys: Vec<&String> = ours.as_object().expect("object").keys().collect();
    let theirs = expected("Monachou");
    assert_eq!(keys.len(), theirs.len());
    assert!(keys.iter().all(|k| theirs.contains_key(*k)));
}
