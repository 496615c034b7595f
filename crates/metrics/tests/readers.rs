//! Readers: the three formats agree on the same cave, and bad input gives errors that name the
//! file, the line and the value (policy in the `readers` module docs).

mod common;

use std::path::{Path, PathBuf};

use common::caves_dir;
use karst_metrics::readers::{read_csv, read_karstnet, read_pline};
use karst_metrics::{Network, ReadError, characterize};
use karst_testkit::scratch;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write test file");
    path
}

/// Asserts a line error and that its message names the file, the line and the value.
fn assert_line_error(result: Result<Network, ReadError>, file: &str, line: usize, value: &str) {
    let err = result.expect_err("bad input must be refused");
    let message = err.to_string();
    assert!(matches!(&err, ReadError::Line { line: l, .. } if *l == line), "{message}");
    assert!(
        message.contains(file) && message.contains(&format!(":{line}:")) && message.contains(value),
        "{message}"
    );
}

#[test]
fn karstnet_files_2d_comments_and_blank_lines() {
    let dir = scratch("dat");
    write(&dir, "c_nodes.dat", "# x y\n0 0\n\n3 4\n6 8\n");
    write(&dir, "c_links.dat", "1 2\n2 3\n");
    let net = read_karstnet(&dir.join("c")).expect("valid");
    assert_eq!(net.nodes, vec![[0.0; 3], [3.0, 4.0, 0.0], [6.0, 8.0, 0.0]]);
    assert_eq!(net.links, vec![[0, 1], [1, 2]]);
}

#[test]
fn karstnet_bad_input() {
    let dir = scratch("dat-bad");
    let base = dir.join("c");
    write(&dir, "c_nodes.dat", "0 0 0\n1 1 1\n2 2 2\n");
    write(&dir, "c_links.dat", "1 2\n3 3\n");
    assert_line_error(read_karstnet(&base), "c_links.dat", 2, "3 3");
    write(&dir, "c_links.dat", "1 2\n2 4\n");
    assert_line_error(read_karstnet(&base), "c_links.dat", 2, "4");
    write(&dir, "c_links.dat", "0 1\n");
    assert_line_error(read_karstnet(&base), "c_links.dat", 1, "0");
    write(&dir, "c_links.dat", "\n");
    assert!(matches!(read_karstnet(&base), Err(ReadError::NoLinks { .. })));
    write(&dir, "c_links.dat", "1 2\n");
    write(&dir, "c_nodes.dat", "0 0 0\n1 nan 1\n");
    assert_line_error(read_karstnet(&base), "c_nodes.dat", 2, "nan");
    write(&dir, "c_nodes.dat", "0 0 0\n1 x1 1\n");
    assert_line_error(read_karstnet(&base), "c_nodes.dat", 2, "x1");
    write(&dir, "c_nodes.dat", "0 0 0\n1 1\n");
    assert_line_error(read_karstnet(&base), "c_nodes.dat", 2, "1 1");
    assert!(matches!(read_karstnet(&dir.join("missing")), Err(ReadError::Io { .. })));
}

#[test]
fn pline_atoms_share_their_vertex() {
    let dir = scratch("pl");
    let text = "GOCAD PLine 1\nILINE\nVRTX 1 0 0 0\nPVRTX 2 1 0 0 7.5\nSEG 1 2\nILINE\nATOM 3 2\nVRTX 4 1 1 0\nSEG 3 4\nEND\n";
    let net = read_pline(&write(&dir, "a.pl", text)).expect("valid");
    assert_eq!(net.nodes.len(), 3);
    assert_eq!(net.links, vec![[0, 1], [1, 2]]);
}

#[test]
fn pline_bad_input() {
    let dir = scratch("pl-bad");
    let self_loop = "VRTX 1 0 0 0\nVRTX 2 1 0 0\nSEG 1 2\nATOM 3 1\nSEG 3 1\n";
    assert_line_error(read_pline(&write(&dir, "a.pl", self_loop)), "a.pl", 5, "SEG 3 1");
    let undefined = "VRTX 1 0 0 0\nVRTX 2 1 0 0\nSEG 1 9\n";
    assert_line_error(read_pline(&write(&dir, "b.pl", undefined)), "b.pl", 3, "9");
    let twice = "VRTX 1 0 0 0\nVRTX 1 1 0 0\n";
    assert_line_error(read_pline(&write(&dir, "c.pl", twice)), "c.pl", 2, "1");
    let infinite = "VRTX 1 0 0 0\nVRTX 2 inf 0 0\n";
    assert_line_error(read_pline(&write(&dir, "d.pl", infinite)), "d.pl", 2, "inf");
}

#[test]
fn csv_ids_and_columns_in_any_order() {
    let dir = scratch("csv");
    let nodes = write(&dir, "n.csv", "z,name,id,x,y\n0,a,100,0,0\n0,b,-5,3,4\n1,c,7,3,4\n");
    let edges = write(&dir, "e.csv", "\"to\",\"from\",kind\n-5,100,x\n7,-5,y\n");
    let net = read_csv(&nodes, &edges).expect("valid");
    assert_eq!(net.nodes, vec![[0.0; 3], [3.0, 4.0, 0.0], [3.0, 4.0, 1.0]]);
    assert_eq!(net.links, vec![[0, 1], [1, 2]]);

    let bad_edges = write(&dir, "bad.csv", "from,to\n100,-5\n100,8\n");
    assert_line_error(read_csv(&nodes, &bad_edges), "bad.csv", 3, "8");
    let loop_edges = write(&dir, "loop.csv", "from,to\n7,7\n");
    assert_line_error(read_csv(&nodes, &loop_edges), "loop.csv", 2, "7,7");
    let no_y = write(&dir, "noy.csv", "id,x,z\n1,0,0\n");
    assert_line_error(read_csv(&no_y, &edges), "noy.csv", 1, "id,x,z");
    let duplicate = write(&dir, "dup.csv", "id,x,y,z\n1,0,0,0\n1,1,1,1\n");
    assert_line_error(read_csv(&duplicate, &edges), "dup.csv", 3, "1");
}

#[test]
fn the_three_formats_agree_on_sakany() {
    let dat = read_karstnet(&caves_dir().join("Sakany")).expect("Sakany");
    let dir = scratch("sakany-csv");
    let mut nodes = String::from("id,x,y,z\n");
    for (i, [x, y, z]) in dat.nodes.iter().enumerate() {
        nodes += &format!("{},{x:?},{y:?},{z:?}\n", 1000 + 3 * i);
    }
    let mut edges = String::from("from,to\n");
    let mut pline = String::from("GOCAD PLine 1\n");
    for (i, [x, y, z]) in dat.nodes.iter().enumerate() {
        pline += &format!("VRTX {} {x:?} {y:?} {z:?}\n", i + 1);
    }
    for [a, b] in &dat.links {
        edges += &format!("{},{}\n", 1000 + 3 * a, 1000 + 3 * b);
        pline += &format!("ILINE\nSEG {} {}\n", a + 1, b + 1);
    }
    let csv = read_csv(&write(&dir, "n.csv", &nodes), &write(&dir, "e.csv", &edges)).expect("csv");
    let pl = read_pline(&write(&dir, "s.pl", &pline)).expect("pline");
    assert_eq!(csv, dat);
    assert_eq!(pl, dat);
    assert_eq!(characterize(&csv), characterize(&dat));
}

/// The layouts real survey tables come in: KNdata's `id;x;y;z` and `from_id;to_id`, 2D tables,
/// `source,target` edges; errors name the file, the line and the column.
#[test]
fn csv_layouts_of_real_data() {
    let dir = scratch("csv-layouts");
    let nodes = write(&dir, "kn_nodes.csv", "id;x;y;z\n1;0.0;0.0;10.5\n2;3.0;4.0;10.0\n3;3.0;8.0;9.0\n");
    let edges = write(&dir, "kn_links.csv", "from_id;to_id\n1;2\n2;3\n");
    let net = read_csv(&nodes, &edges).expect("KNdata layout");
    assert_eq!(net.nodes, vec![[0.0, 0.0, 10.5], [3.0, 4.0, 10.0], [3.0, 8.0, 9.0]]);
    assert_eq!(net.links, vec![[0, 1], [1, 2]]);

    let flat = write(&dir, "flat.csv", "ID,X,Y\n1,0,0\n2,3,4\n3,3,8\n");
    let st = write(&dir, "st.csv", "\"source\",\"target\",length\n1,2,5\n2,3,4\n");
    let net2d = read_csv(&flat, &st).expect("2D nodes, source/target edges");
    assert_eq!(net2d.nodes, vec![[0.0; 3], [3.0, 4.0, 0.0], [3.0, 8.0, 0.0]]);
    assert_eq!(net2d.links, net.links);

    let bad_x = write(&dir, "bad_x.csv", "id;x;y;z\n1;0;0;0\n2;1,5;0;0\n");
    let err = read_csv(&bad_x, &edges).unwrap_err().to_string();
    assert!(err.contains("bad_x.csv:3:") && err.contains("column 2 (`x`)") && err.contains("1,5"), "{err}");
    let short = write(&dir, "short.csv", "id;x;y;z\n1;0;0\n");
    let err = read_csv(&short, &edges).unwrap_err().to_string();
    assert!(err.contains("short.csv:2:") && err.contains("missing column 4 (`z`)"), "{err}");
    let no_ends = write(&dir, "no_ends.csv", "a;b\n1;2\n");
    let err = read_csv(&nodes, &no_ends).unwrap_err().to_string();
    assert!(err.contains("no_ends.csv:1:") && err.contains("`from_id`/`to_id`"), "{err}");
}

/// `--karstnet` takes the base name or either file's name.
#[test]
fn karstnet_base_or_either_file() {
    let base = caves_dir().join("Sakany");
    let whole = read_karstnet(&base).expect("Sakany");
    for name in ["Sakany_nodes.dat", "Sakany_links.dat"] {
        assert_eq!(read_karstnet(&caves_dir().join(name)).expect(name), whole);
    }
    assert_eq!(karst_metrics::readers::karstnet_base(Path::new("a/_nodes.dat")), Path::new("a/_nodes.dat"));
}
