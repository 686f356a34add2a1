//! The claims engine's unit tests: verdict words per kind, context checks, the per-map
//! aggregation, bounds and equality, untestable evidence.

use super::outcome::*;
use super::verdict::*;
use crate::claims::declaration::parse::parse;
use crate::claims::declaration::{Kind, Paper};
use std::path::Path;

/// A paper with one claim of `kind` and the given checks; maps m1..m4 (m1, m2 the "paper"
/// set).
fn paper(checks: &str, kind: &str) -> Paper {
    let text = format!(
        "title='T'\nauthors='A'\nvenue='V'\norder=1\n[map_sets]\npaper=['m1','m2']\n[[claim]]\nid='X1'\nsays='s'\n\
         paper_figure='p'\ncriterion='c'\nkind='{kind}'\nfixed='before data'\ndiffers='d'\nquote='the paper states 0.5'\nthreshold_from='{from}'\n{checks}",
        from = if kind == "anchor" { "none" } else { "paper: 0.5" }
    );
    parse("t", &text, Path::new("t.toml")).unwrap()
}

fn table() -> Evidence {
    // a/b ratios: m1 0.5, m2 0.8, m3 1.5; m4 baseline 1e-9 (ratio 1e6).
    let csv = "map,encoder,metric,rmse\nm1,a,exact,0.5\nm1,b,exact,1\nm2,a,exact,0.8\nm2,b,exact,1\n\
               m3,a,exact,3\nm3,b,exact,2\nm4,a,exact,0.001\nm4,b,exact,1e-9\nm1,a,peer,9\nm1,b,peer,1\n";
    Evidence::parse(csv.as_bytes(), Path::new("t.csv")).unwrap()
}

fn judge_on(checks: &str, kind: &str, t: &Evidence) -> ClaimOutcome {
    let p = paper(checks, kind);
    judge_claim(&p, &p.claims[0], &|_| Ok(t.clone()))
}

fn judge(checks: &str, kind: &str) -> ClaimOutcome {
    judge_on(checks, kind, &table())
}

const CHECK: &str = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nwhere={metric='exact'}\n";
const PRIMARY: &str =
    "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nwhere={metric='exact'}\nrole='primary'\n";

#[test]
fn measured_is_partly_when_the_primary_holds_on_one_set_only() {
    let o = judge(&format!("{PRIMARY}test='ratio_every'\nfloor=1e-6\non=['paper','all']"), "measured");
    assert_eq!(o.verdict.word(), "partly", "{:?}", o.verdict);
    assert!(o.verdict.why().contains("holds on paper (2 maps), not on all (4 maps)"), "{}", o.verdict.why());
    let all = &o.checks[0].sets[1];
    // m4 is left out by the floor and counted.
    assert_eq!(all.values.len(), 3);
    assert_eq!(all.excluded, 1);
    assert!(all.figure.contains("1 with b rmse ≤ floor"), "{}", all.figure);
    let o = judge(&format!("{PRIMARY}test='ratio_every'\nbelow=0.4\nfloor=1e-6"), "measured");
    assert_eq!(o.verdict.word(), "fails");
    assert_eq!(judge(&format!("{PRIMARY}test='ratio_some'\nbelow=0.6"), "measured").verdict, Verdict::Holds);
}

/// Each kind has its own words: the same passing and failing primaries give them.
#[test]
fn each_kind_gets_its_own_words() {
    let pass = format!("{PRIMARY}test='ratio_some'\nbelow=0.6");
    let fail = format!("{PRIMARY}test='ratio_every'\nbelow=0.4\nfloor=1e-6");
    assert_eq!(judge(&pass, "identity").verdict, Verdict::HoldsIdentity);
    assert_eq!(judge(&fail, "identity").verdict.word(), "fails");
    assert_eq!(judge(&pass, "example").verdict, Verdict::Reproduced);
    assert_eq!(judge(&fail, "example").verdict.word(), "not reproduced");
    // An anchor's figure is shown (median of the per-map ratios 0.8 over m1..m3) and never
    // holds or fails.
    let o = judge(&format!("{PRIMARY}test='ratio_summary'\nfloor=1e-6"), "anchor");
    assert_eq!(o.verdict, Verdict::NotComparable);
    assert_eq!(o.checks[0].sets[0].status, Status::Shown);
    assert!(o.our_figure().contains("per-map median 0.800"), "{}", o.our_figure());
    for k in [Kind::Identity, Kind::Measured, Kind::Example] {
        assert!(k.verdict_words().contains(&judge(&pass, k.as_str()).verdict.word()));
        assert!(k.verdict_words().contains(&judge(&fail, k.as_str()).verdict.word()));
    }
    // Missing evidence is untestable for every kind, never passed.
    for k in Kind::ALL {
        let check = if k == Kind::Anchor { "test='ratio_summary'" } else { "test='ratio_every'" };
        let p = paper(&format!("{PRIMARY}{check}"), k.as_str());
        let o = judge_claim(&p, &p.claims[0], &|_| Err("results/e/table.csv: not found".into()));
        assert_eq!(o.verdict.word(), "untestable");
        assert!(o.verdict.why().contains("not found"));
    }
}

/// A context check is shown and judged, and never changes the verdict, whether it passes
/// or fails, however many there are.
#[test]
fn context_checks_never_change_the_verdict() {
    let primary = format!("{PRIMARY}test='ratio_some'\nbelow=0.6");
    let failing_context = format!("{CHECK}test='ratio_every'\nbelow=0.1\n");
    let passing_context = format!("{CHECK}test='ratio_some'\nbelow=2\n");
    let alone = judge(&primary, "measured");
    for extra in [&failing_context, &passing_context] {
        for n in 1..4 {
            let o = judge(&format!("{primary}\n{}", extra.repeat(n).replace("name='n'", "name='c'")), "measured");
            assert_eq!(o.verdict, alone.verdict);
            assert_eq!(o.checks.len(), n + 1);
        }
    }
    // A context check declared `beside` stands beside the primary's figure.
    let beside = format!("{primary}\n{}beside=true\n", failing_context.replace("name='n'", "name='cost'"));
    let o = judge(&beside, "measured");
    assert_eq!(o.verdict, Verdict::Holds);
    assert!(o.our_figure().contains(" · cost: 0/"), "{}", o.our_figure());
}

/// The aggregation rule: ratios per map (the geometric mean of a map's rows), summarised by
/// median and geometric mean; never a ratio of pooled means. On this table one map with
/// large errors (big) makes the pooled ratio Σa/Σb = (0.4 + 0.3 + 0.45 + 20 + 20) / (1 + 1 +
/// 1 + 10 + 40) = 0.776, while the per-map ratios are 0.4, 0.3, 0.45 and 1: median 0.425, geometric
/// mean (0.054)^(1/4) = 0.4821. "Below 0.5" holds by the median and the geometric mean,
/// and would fail by the pooled ratio.
#[test]
fn per_map_median_and_geomean_decide_where_the_pooled_ratio_disagrees() {
    const PRIMARY: &str = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nrole='primary'\n";
    let t = Evidence::parse(
        b"map,encoder,case,rmse\ns1,a,up,0.4\ns1,b,up,1\ns2,a,up,0.3\ns2,b,up,1\ns3,a,up,0.45\ns3,b,up,1\n\
          big,a,up,20\nbig,b,up,10\nbig,a,down,20\nbig,b,down,40\n",
        Path::new("t.csv"),
    )
    .unwrap();
    // The pooled ratio, by hand from the table: 41.15 / 53 = 0.776 over rows, not below 0.5.
    let (sa, sb) = (0.4 + 0.3 + 0.45 + 20.0 + 20.0, 1.0 + 1.0 + 1.0 + 10.0 + 40.0);
    assert!(sa / sb > 0.5);
    // big: rows 2 and 0.5, per-map ratio (2 · 0.5)^(1/2) = 1.
    let med = judge_on(&format!("{PRIMARY}test='ratio_stat'\nstatistic='median'\nmax=0.5"), "measured", &t);
    assert_eq!(med.verdict, Verdict::Holds, "{}", med.checks[0].sets[0].figure);
    assert!(
        med.our_figure().starts_with("per-map median 0.425 ≤ 0.500 (geomean 0.482; 3/4 maps ≤ 0.500)"),
        "{}",
        med.our_figure()
    );
    let gm = judge_on(&format!("{PRIMARY}test='ratio_stat'\nstatistic='geomean'\nmax=0.5"), "measured", &t);
    assert_eq!(gm.verdict, Verdict::Holds);
    let gm_tight = judge_on(&format!("{PRIMARY}test='ratio_stat'\nstatistic='geomean'\nmax=0.48"), "measured", &t);
    assert_eq!(gm_tight.verdict.word(), "fails");
    // The per-map values are what the page lists: one per map, big at 1.
    let v = &med.checks[0].sets[0].values;
    assert_eq!(v.len(), 4);
    assert!(v[3].label.starts_with("big (2 rows)") && (v[3].value - 1.0).abs() < 1e-15, "{:?}", v[3]);
    // Per map, 3 of 4 maps are below 0.5; per row, 3 of 5 rows.
    let pm = judge_on(&format!("{PRIMARY}test='ratio_some'\nbelow=0.5\nper_map=true"), "measured", &t);
    assert!(pm.our_figure().starts_with("3/4 maps < 0.500"), "{}", pm.our_figure());
    let pr = judge_on(&format!("{PRIMARY}test='ratio_some'\nbelow=0.5"), "measured", &t);
    assert!(pr.our_figure().starts_with("3/5 rows < 0.500"), "{}", pr.our_figure());
    // No figure names a ratio of means.
    for o in [&med, &gm, &pm, &pr] {
        assert!(!o.checks[0].sets[0].figure.contains("of means"), "{}", o.checks[0].sets[0].figure);
    }
}

#[test]
fn bounds_and_equality() {
    let at = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nwhere={metric='exact'}\nrole='primary'\n";
    assert_eq!(judge(&format!("{at}test='every_at_most'\nbound=3"), "measured").verdict, Verdict::Holds);
    assert_eq!(judge(&format!("{at}test='every_at_most'\nbound=2"), "measured").verdict.word(), "fails");
    assert_eq!(judge(&format!("{at}test='every_at_least'\nbound=0.5"), "measured").verdict.word(), "fails");
    assert_eq!(judge(&format!("{PRIMARY}test='equal'\ntolerance=0.01"), "identity").verdict.word(), "fails");
    let same = Evidence::parse(b"map,encoder,rmse\nm1,a,0.5\nm1,b,0.5000000000001\n", Path::new("t")).unwrap();
    let p = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nrole='primary'\ntest='equal'\n";
    assert_eq!(judge_on(p, "identity", &same).verdict, Verdict::HoldsIdentity);
}

#[test]
fn missing_maps_and_columns_are_untestable() {
    let p = paper(&format!("{PRIMARY}test='ratio_every'\non=['paper']\nmaps=['m1','m2']"), "measured");
    let t = Evidence::parse(b"map,encoder,metric,rmse\nm1,a,exact,1\nm1,b,exact,2\n", Path::new("t")).unwrap();
    let o = judge_claim(&p, &p.claims[0], &|_| Ok(t.clone()));
    assert_eq!(o.verdict.word(), "untestable");
    assert!(o.verdict.why().contains("m2"), "{}", o.verdict.why());
    let o = judge(&format!("{PRIMARY}test='ratio_every'\ncolumn='speed'"), "measured");
    assert!(o.verdict.why().contains("no column 'speed'"), "{}", o.verdict.why());
}

/// Constructed scenes are never pooled with maps: `all` judges the maps only, `scenes` the
/// scenes only, each labelled with what it holds.
#[test]
fn scenes_and_maps_are_judged_apart() {
    let t = Evidence::parse(
        b"map,encoder,rmse\nm1,a,0.5\nm1,b,1\nm2,a,0.8\nm2,b,1\ngen_x,a,3\ngen_x,b,1\nconstructed_y,a,0.1\nconstructed_y,b,1\n",
        Path::new("t.csv"),
    )
    .unwrap();
    let p = "[[claim.check]]\nname='n'\ntable='e'\nencoder='a'\nbaseline='b'\nrole='primary'\ntest='ratio_every'\n";
    let o = judge_on(&format!("{p}on=['all','scenes']"), "measured", &t);
    let (all, scenes) = (&o.checks[0].sets[0], &o.checks[0].sets[1]);
    assert_eq!(all.values.len(), 2, "{:?}", all.values);
    assert!(all.values.iter().all(|v| v.label.starts_with('m')));
    assert_eq!(all.status, Status::Pass);
    assert_eq!(scenes.values.len(), 2);
    assert_eq!(scenes.status, Status::Fail);
    assert_eq!(o.maps(), "all (2 maps); scenes (2 constructed scenes)");
    assert_eq!(o.verdict.word(), "partly");
}

/// A check restricted to some maps (`maps = [...]`) says which: its set is labelled by the
/// maps it holds, never as the whole set.
#[test]
fn a_restricted_set_names_its_maps() {
    let o = judge(&format!("{PRIMARY}test='ratio_every'\nbelow=1.0\non=['all']\nmaps=['m1','m2']"), "measured");
    assert_eq!(o.maps(), "m1, m2 (of all; 2 maps)");
    let o = judge(&format!("{PRIMARY}test='ratio_every'\nbelow=1.0\non=['all']"), "measured");
    assert_eq!(o.maps(), "all (4 maps)");
}
