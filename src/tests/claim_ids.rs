//! The paper claims' ids: every claim declared once (`claims::declaration`), its id in the
//! committed `results/CLAIMS.csv` and, where the paper texts lie beside the repository, in
//! their `CLAIMS.md`; the committed verdicts of their declared kind. `probelab claims` itself
//! runs in `tests/claims.rs`.

use super::repository::{parse_csv, repo};
use crate::claims::declaration::load_papers;
use std::collections::{BTreeSet, HashSet};

/// The claim ids of a Markdown table: the first cell of every row whose first cell is an id (an
/// upper-case letter, then digits: `| H1 | … |`), in order. The header and separator rows are
/// not ids.
fn table_ids(markdown: &str) -> Vec<String> {
    markdown
        .lines()
        .filter_map(|l| l.trim().strip_prefix('|')?.split('|').next().map(str::trim))
        .filter(|c| {
            let mut ch = c.chars();
            ch.next().is_some_and(|a| a.is_ascii_uppercase())
                && !ch.as_str().is_empty()
                && ch.as_str().chars().all(|d| d.is_ascii_digit())
        })
        .map(String::from)
        .collect()
}

/// `a` and `b` hold the same ids; otherwise a message naming those only in one of them.
fn same_ids(a: &[String], b: &[String], (name_a, name_b): (&str, &str)) -> Result<(), String> {
    let (sa, sb): (BTreeSet<&String>, BTreeSet<&String>) = (a.iter().collect(), b.iter().collect());
    if sa == sb {
        return Ok(());
    }
    Err(format!(
        "only in {name_a}: {:?}; only in {name_b}: {:?}",
        sa.difference(&sb).collect::<Vec<_>>(),
        sb.difference(&sa).collect::<Vec<_>>()
    ))
}

/// Every paper claim is declared exactly once: the declared ids are unique and are the ids of
/// the committed `results/CLAIMS.csv` (one verdict per claim), and, where the paper texts'
/// `CLAIMS.md` lies beside the repository (`../shared/papers/CLAIMS.md`, as in CI), the ids of
/// its table. No id is written here: a claim added to CLAIMS.md and not declared fails.
#[test]
fn every_paper_claim_is_declared_once() {
    let papers = load_papers(&repo().join("experiments")).unwrap();
    let ids: Vec<String> = papers.iter().flat_map(|p| p.claims.iter().map(|c| c.id.clone())).collect();
    assert!(!ids.is_empty(), "no claim declared in experiments/claims/");
    let got: HashSet<&String> = ids.iter().collect();
    assert_eq!(got.len(), ids.len(), "an id declared twice: {ids:?}");
    let csv = parse_csv(&std::fs::read_to_string(repo().join("results/CLAIMS.csv")).unwrap());
    let judged: Vec<String> = csv.iter().map(|r| r["id"].clone()).collect();
    assert_eq!(judged.iter().collect::<HashSet<_>>().len(), judged.len(), "an id twice in CLAIMS.csv: {judged:?}");
    same_ids(&ids, &judged, ("experiments/claims/", "results/CLAIMS.csv")).unwrap();
    let claims_md = repo().join("../shared/papers/CLAIMS.md");
    if claims_md.is_file() {
        let listed = table_ids(&std::fs::read_to_string(&claims_md).unwrap());
        assert!(!listed.is_empty(), "{}: no claim rows (`| H1 | … |`)", claims_md.display());
        assert_eq!(listed.iter().collect::<HashSet<_>>().len(), listed.len(), "an id twice in CLAIMS.md: {listed:?}");
        same_ids(&ids, &listed, ("experiments/claims/", "CLAIMS.md")).unwrap();
    }
    // Report order: the ZH3 talk, the hemispherical talk, the 2018 brief.
    let keys: Vec<&str> = papers.iter().map(|p| p.key.as_str()).collect();
    assert_eq!(keys, ["zh3", "hemi", "brief2018"]);
}

/// The reader of CLAIMS.md's table and the comparison fail when they should: a header, a
/// separator and prose are not ids; a missing or an extra id is named.
#[test]
fn claim_ids_are_read_from_the_table_and_compared() {
    let md = "# Claims\n\n| id | claim | source |\n|---|---|---|\n| H1 | a | talk |\n| Z10 | b | talk |\n\
              text | X1 | not a row\n| D2 | c |\n";
    let ids = table_ids(md);
    assert_eq!(ids, ["H1", "Z10", "D2"]);
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    assert!(same_ids(&ids, &s(&["D2", "H1", "Z10"]), ("a", "b")).is_ok());
    let err = same_ids(&ids, &s(&["H1", "Z10", "D3"]), ("a", "b")).unwrap_err();
    assert!(err.contains("only in a: [\"D2\"]") && err.contains("only in b: [\"D3\"]"), "{err}");
}

/// The committed verdicts (`results/CLAIMS.csv`, which `probelab claims` on the committed
/// evidence reproduces: `tests/claims.rs`) are of their declared kind, each verdict one of the
/// words that kind allows.
#[test]
fn the_committed_verdicts_are_of_their_declared_kind() {
    let papers = load_papers(&repo().join("experiments")).unwrap();
    let rows = parse_csv(&std::fs::read_to_string(repo().join("results/CLAIMS.csv")).unwrap());
    assert_eq!(rows.len(), 22);
    for r in &rows {
        // The kind is the declared one, and the verdict one of the words it allows.
        let decl = papers.iter().flat_map(|p| &p.claims).find(|c| c.id == r["id"]).unwrap();
        assert_eq!(r["kind"], decl.kind.as_str(), "{r:?}");
        let v = r["verdict"].as_str();
        assert!(decl.kind.verdict_words().contains(&v) || v == "untestable", "{r:?}");
    }
}
