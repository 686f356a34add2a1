//! A new user's first hour on a fresh clone, without the shared maps (`PROBELAB_ENVMAPS`
//! unset): `check` passes on the maps present and says in one line what it could not check,
//! each missing map is named once with the fix, typos get the nearest name, experiments run by
//! name, commands outside a checkout say where to run, and `maps` lists the known maps missing
//! with where to get them.

mod common;

use common::harness::{probelab, repo, Run, Scratch};
use std::process::Output;

fn text(o: &Output) -> (String, String) {
    (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// A scratch checkout with three maps of its own (copies of generated maps, under names no
/// known map has) and two experiments: `small_sphere` on a and b, `small_floor` on b alone.
fn checkout() -> Scratch {
    let root = Scratch::new();
    root.copy_from_repo("tolerances.toml");
    for (name, src) in [("a", "gen_sun_sky"), ("b", "gen_two_lights")] {
        root.write(&format!("envmaps/{name}.exr"), std::fs::read(repo().join(format!("envmaps/{src}.exr"))).unwrap());
    }
    root.write("experiments/small_sphere.toml", "maps = ['a', 'b']\nencoders = ['sh1', 'sh2']\nresolution = [16, 8]\n");
    root.write("experiments/small_floor.toml", "maps = ['b']\nencoders = ['sh1']\nresolution = [16, 8]\n");
    root
}

/// The rows of `results/<exp>/table.csv` on map `map`, counted from the CSV itself.
fn rows_on(root: &Scratch, exp: &str, map: &str) -> usize {
    let t = std::fs::read_to_string(root.path().join("results").join(exp).join("table.csv")).unwrap();
    common::harness::parse_csv(&t).iter().filter(|r| r["map"] == map).count()
}

#[test]
fn check_passes_on_the_maps_here_and_says_once_what_it_could_not_check() {
    let root = checkout();
    // Experiments by name, not only by file.
    let out = root.run(&["--no-timing", "run", "small_sphere", "small_floor"]);
    let (so, se) = text(&out);
    assert!(out.status.success(), "{so}{se}");
    let unchecked = rows_on(&root, "small_sphere", "b") + rows_on(&root, "small_floor", "b");
    assert!(unchecked > 0);
    std::fs::remove_file(root.path().join("envmaps/b.exr")).unwrap();

    let out = root.run(&["--no-timing", "check"]);
    let (so, se) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{so}{se}");
    let lines: Vec<&str> = so.lines().filter(|l| l.starts_with("not checked here: ")).collect();
    assert_eq!(lines.len(), 1, "{so}");
    assert!(
        lines[0].starts_with(&format!(
            "not checked here: 1 map(s) missing (b): 1 experiment(s) skipped, 1 run on part of their maps, \
             {unchecked} baseline row(s) not compared"
        )),
        "{}",
        lines[0]
    );
    assert!(!so.contains("bless"), "nothing to bless when only maps are missing: {so}");
    // The missing map once, with the fix once.
    assert_eq!(se.matches("  b (read by 2 experiment(s))").count(), 1, "{se}");
    assert_eq!(se.matches("PROBELAB_ENVMAPS=").count(), 1, "{se}");
    assert!(!so.contains("map b not found"), "{so}");

    // A CI that owns its maps makes a missing one an error; the old flag is still accepted.
    let out = root.run(&["--no-timing", "check", "--require-all-maps"]);
    let (so, se) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{so}{se}");
    assert!(
        so.contains("small_sphere: map b not found on this machine") && so.contains("Only maps are missing"),
        "{so}"
    );
    let out = root.run(&["--no-timing", "check", "--allow-missing"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out).0);
}

/// Whether `text` opens a parenthesis inside another (`(a (b))`), which reads badly in a message.
fn nests_parentheses(text: &str) -> bool {
    let mut depth = 0i32;
    for c in text.chars() {
        match c {
            '(' if depth >= 1 => return true,
            '(' => depth += 1,
            ')' => depth = (depth - 1).max(0),
            _ => {}
        }
    }
    false
}

#[test]
fn typos_get_the_nearest_name() {
    let out = probelab().args(["eval", "gen_sky_su", "--encoders", "sh1", "--resolution", "8x4"]).run();
    let (_, se) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("gen_sky_su (no file of that name on the search path; did you mean 'gen_sky_sun'?)"), "{se}");
    assert!(!nests_parentheses(&se), "{se}");

    // A path is read as given: it says so, and lists no folder it was never looked up in.
    let out = probelab().args(["eval", "envmaps/nope.exr", "--encoders", "sh1", "--resolution", "8x4"]).run();
    let (_, se) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("envmaps/nope.exr (no such file)"), "{se}");
    assert!(!se.contains("Searched") && !nests_parentheses(&se), "{se}");

    // A difference of case alone gets the name meant.
    let out = probelab().args(["eval", "gen_sky_sun", "--encoders", "SH2", "--resolution", "8x4"]).run();
    let (_, se) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("unknown encoder 'SH2' (did you mean 'sh2'?)"), "{se}");

    let out = probelab().args(["eval", "gen_sky_sun", "--encoders", "sh1,sh22", "--resolution", "8x4"]).run();
    let (_, se) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("unknown encoder 'sh22' (did you mean 'sh2'?)"), "{se}");

    let out = probelab().args(["check", "sh_baselin"]).run();
    let (_, se) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("experiment 'sh_baselin': ") && se.contains("did you mean 'sh_baseline'?"), "{se}");

    let root = checkout();
    let out = root.run(&["run", "small_sphre"]);
    let (_, se) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{se}");
    assert!(se.contains("did you mean 'small_sphere'?"), "{se}");
    assert!(!root.path().join("results").exists(), "a typo wrote nothing");
}

#[test]
fn outside_a_checkout_commands_say_where_to_run() {
    let empty = tempfile::tempdir().unwrap();
    for args in [vec!["check"], vec!["reproduce"], vec!["report"], vec!["run", "sh_baseline"]] {
        // Without --root (the current folder), and with a --root that is no checkout.
        let here = probelab().current_dir(empty.path()).args(&args).run();
        let there = probelab().arg("--root").arg(empty.path()).args(&args).run();
        for out in [here, there] {
            let (so, se) = text(&out);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {so}{se}");
            assert!(se.contains("run inside a probelab checkout or pass `--root`"), "{args:?}: {se}");
        }
    }
    assert!(std::fs::read_dir(empty.path()).unwrap().next().is_none(), "nothing written outside a checkout");
}

#[test]
fn maps_lists_the_known_maps_missing_with_where_to_get_them() {
    let out = probelab().arg("maps").run();
    let (so, se) = text(&out);
    assert!(out.status.success(), "{se}");
    // A known map is here when a file under its name or an alias is in envmaps/.
    let here = |names: &[&String]| {
        names.iter().any(|n| ["exr", "hdr"].iter().any(|x| repo().join(format!("envmaps/{n}.{x}")).is_file()))
    };
    let mut missing = 0;
    // The known maps as `envmaps/known.toml` declares them (the table the binary compiles in).
    let known: toml::Table = std::fs::read_to_string(repo().join("envmaps/known.toml")).unwrap().parse().unwrap();
    let text = |k: &toml::Value, key: &str| k[key].as_str().unwrap().to_string();
    for k in known["map"].as_array().unwrap() {
        let name = text(k, "name");
        let aliases: Vec<String> =
            k["aliases"].as_array().unwrap().iter().map(|a| a.as_str().unwrap().into()).collect();
        let names: Vec<&String> = std::iter::once(&name).chain(&aliases).collect();
        let line = format!("  {name} ({}x{}): {}\n", k["width"], k["height"], text(k, "get"));
        if here(&names) {
            assert!(!so.contains(&line), "{name} is here: {so}");
        } else {
            assert!(so.contains(&line), "{name} missing, not listed: {so}");
            missing += 1;
        }
    }
    assert!(missing > 0, "the paper probes are not committed");
    assert!(so.contains(&format!("known maps not found ({missing}; ")), "{so}");
}
