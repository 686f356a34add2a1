//! The claims engine end to end: the declarations in `experiments/claims/` cover the papers'
//! claims once each; `probelab claims` on the committed evidence writes one verdict per id;
//! and a constructed claim on a constructed table comes out `fails`. Nothing here requires a
//! paper claim to hold.

mod common;

use common::harness::{parse_csv, repo, Scratch};

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
    for r in &rows {
        // The kind and verdict are the committed ones, which are the declared kind and one of
        // the words it allows (`src/tests/claim_ids.rs`).
        assert!(r["detail"].starts_with("claims/") && r["detail"].contains(".md#"), "{r:?}");
        assert!(!r["criterion"].is_empty() && !r["paper_figure"].is_empty(), "{r:?}");
    }
    // The committed verdicts are what the committed evidence gives (`check` fails otherwise).
    let committed = parse_csv(&std::fs::read_to_string(repo().join("results/CLAIMS.csv")).unwrap());
    for (a, b) in rows.iter().zip(&committed) {
        assert_eq!((&a["id"], &a["verdict"]), (&b["id"], &b["verdict"]));
        assert_eq!(a["kind"], b["kind"], "{a:?}");
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
         kind='measured'\nfixed='before data'\ndiffers='d'\nquote='the paper states 0.5'\nthreshold_from='paper: 0.5'\n\
         [[claim.check]]\nname='a/b'\ntable='exp'\nencoder='a'\nbaseline='b'\ntest='ratio_every'\nbelow=0.7\n\
         role='primary'\n\
         [[claim]]\nid='X2'\nsays='needs data'\npaper_figure='p'\ncriterion='c'\n\
         kind='identity'\nfixed='before data'\ndiffers='d'\nquote='q'\nthreshold_from='rounding'\n\
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

/// Every figure a claim shows beside its paragraph is a committed file under `results/`, so a
/// fresh clone's evidence pages show it without any map.
#[test]
fn every_claims_figure_is_a_file_under_results() {
    let mut n = 0;
    for paper in ["zh3", "hemi", "brief2018"] {
        let text = std::fs::read_to_string(repo().join(format!("experiments/claims/{paper}.toml"))).unwrap();
        let page = std::fs::read_to_string(repo().join(format!("results/claims/{paper}.md"))).unwrap();
        for line in text.lines().filter(|l| l.starts_with("figure = ")) {
            // A claim may show several figures (a list of tables); each is checked.
            for image in line.split("image = \"").skip(1).filter_map(|r| r.split('"').next()) {
                assert!(repo().join("results").join(image).is_file(), "{paper}: {image}");
                assert!(page.contains(&format!("](../{image})")), "{paper}: {image} is not on the page");
            }
            n += 1;
        }
    }
    assert!(n >= 6, "H2, H3, H5, H8, H9 and Z2 each show a figure ({n} found)");
}
