//! The claims engine end to end: the declarations in `experiments/claims/` cover the papers'
//! claims once each; `probelab claims` on the committed evidence writes one verdict per id;
//! and a constructed claim on a constructed table comes out `fails`. Nothing here requires a
//! paper claim to hold.

mod common;

use common::harness::{parse_csv, repo, Scratch};
use probelab::claims::declaration::load_papers;
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

/// `probelab claims` on a copy of the committed results, without the shared maps: the
/// measurements are not taken (and say so), the committed evidence is judged, and CLAIMS.csv
/// has one row per id with one valid verdict and a relative link to its evidence.
#[test]
fn claims_on_the_committed_evidence_give_one_verdict_per_id() {
    let s = Scratch::new();
    s.copy_from_repo("experiments");
    s.copy_from_repo("results");
    s.copy_from_repo("tolerances.toml");
    let out = s.run(&["claims"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("measurements not taken"), "{stdout}");
    let rows = parse_csv(&std::fs::read_to_string(s.path().join("results/CLAIMS.csv")).unwrap());
    assert_eq!(rows.len(), 22);
    let papers = load_papers(&repo().join("experiments")).unwrap();
    for r in &rows {
        // The kind is the declared one, and the verdict one of the words it allows.
        let decl = papers.iter().flat_map(|p| &p.claims).find(|c| c.id == r["id"]).unwrap();
        assert_eq!(r["kind"], decl.kind.as_str(), "{r:?}");
        let v = r["verdict"].as_str();
        assert!(decl.kind.verdict_words().contains(&v) || v == "untestable", "{r:?}");
        assert!(r["detail"].starts_with("claims/") && r["detail"].contains(".md#"), "{r:?}");
        assert!(!r["criterion"].is_empty() && !r["paper_figure"].is_empty(), "{r:?}");
    }
    // The committed verdicts are what the committed evidence gives (`check` fails otherwise).
    let committed = parse_csv(&std::fs::read_to_string(repo().join("results/CLAIMS.csv")).unwrap());
    for (a, b) in rows.iter().zip(&committed) {
        assert_eq!((&a["id"], &a["verdict"]), (&b["id"], &b["verdict"]));
    }
}

/// A claim declared on a constructed table, whose criterion the table does not meet, comes out
/// `fails`; a claim whose evidence is absent comes out `untestable`, never `holds`.
#[test]
fn a_failing_claim_is_reported_as_failing() {
    let s = Scratch::new();
    s.copy_from_repo("tolerances.toml");
    s.write(
        "experiments/claims/t.toml",
        "title='T'\nauthors='A'\nvenue='V'\norder=1\n\
         [[claim]]\nid='X1'\nsays='a beats b by half'\npaper_figure='p'\ncriterion='a/b < 0.5 on every map'\n\
         kind='measured'\nfixed='before data'\ndiffers='d'\n\
         [[claim.check]]\nname='a/b'\ntable='exp'\nencoder='a'\nbaseline='b'\ntest='ratio_every'\nbelow=0.7\n\
         role='primary'\n\
         [[claim]]\nid='X2'\nsays='needs data'\npaper_figure='p'\ncriterion='c'\n\
         kind='identity'\nfixed='before data'\ndiffers='d'\n\
         [[claim.check]]\nname='missing'\ntable='nothing_here'\nencoder='a'\ntest='every_at_most'\nbound=1\n\
         role='primary'\n",
    );
    s.write("results/exp/table.csv", "map,encoder,rmse\nm1,a,0.6\nm1,b,1\nm2,a,0.4\nm2,b,1\n");
    let out = s.run(&["claims"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = parse_csv(&std::fs::read_to_string(s.path().join("results/CLAIMS.csv")).unwrap());
    assert_eq!((rows[0]["kind"].as_str(), rows[0]["verdict"].as_str()), ("measured", "holds"));
    assert_eq!((rows[1]["kind"].as_str(), rows[1]["verdict"].as_str()), ("identity", "untestable"));
    let page = std::fs::read_to_string(s.path().join("results/claims/t.md")).unwrap();
    assert!(page.contains("nothing_here/table.csv"), "{page}");
    // Every claim has its "What we found" paragraph, with our figure and the verdict.
    assert_eq!(page.matches("**What we found.**").count(), 2, "{page}");
    assert!(page.contains("We measure 2/2 maps < 0.700"), "{page}");
    // The paper's own wording, "by half": one map of two passes, so the claim fails.
    let text = std::fs::read_to_string(s.path().join("experiments/claims/t.toml")).unwrap();
    s.write("experiments/claims/t.toml", text.replace("below=0.7", "below=0.5"));
    let out = s.run(&["claims"]);
    assert_eq!(out.status.code(), Some(0));
    let rows = parse_csv(&std::fs::read_to_string(s.path().join("results/CLAIMS.csv")).unwrap());
    assert_eq!(rows[0]["verdict"], "fails");
}

/// No absolute machine path in any committed result file.
#[test]
fn results_hold_no_absolute_paths() {
    let home = std::env::var("HOME").unwrap_or_default();
    let mut stack = vec![repo().join("results")];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if matches!(p.extension().and_then(|x| x.to_str()), Some("csv" | "md" | "toml")) {
                let t = std::fs::read_to_string(&p).unwrap();
                for bad in ["/work/", "/home/", "/root/", "/tmp/"] {
                    assert!(!t.contains(bad), "{} contains {bad}", p.display());
                }
                if home.len() > 1 {
                    assert!(!t.contains(&home), "{} contains $HOME", p.display());
                }
            }
        }
    }
}
