"""The results viewer (results/site/, written by `probelab report`) in a real browser: headless
Chromium (the system's, /usr/bin/chromium, or PROBELAB_CHROMIUM) driven by Playwright for
Python, software WebGL2. Run by tests/viewer.rs with the interpreter PROBELAB_PYTHON names (where
`pip install ./bindings/python playwright pytest` was run); PROBELAB_BIN is the binary.

Expected values come from the library, not from the page: the Python package's `irradiance`
(the library's reconstruction at given normals) and the binary's `eval --format json` (the
RMSE over the same grid, metric and domain). Without Playwright or Chromium the tests skip with
the reason, except in CI (CI=true), where they fail.
"""
import base64
import hashlib
import json
import math
import os
import pathlib
import random
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SITE = REPO / "results" / "site"
CHROMIUM = os.environ.get("PROBELAB_CHROMIUM", "/usr/bin/chromium")
IN_CI = os.environ.get("CI") in ("true", "1")
# A CC0 map committed in envmaps/ (so a fresh clone has it) and the analytic constant scene.
MAP = "blender_city_256x128"
CONSTANT = "gen_constant"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--no-first-run", "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader", "--allow-file-access-from-files"]


def _missing():
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "Playwright for Python is not installed (pip install playwright)"
    if not pathlib.Path(CHROMIUM).exists():
        return f"no Chromium at {CHROMIUM} (apt-get install chromium)"
    if not (SITE / "index.html").is_file():
        return "results/site/index.html is absent (probelab report writes it)"
    return None


@pytest.fixture(scope="module")
def browser():
    why = _missing()
    if why:
        if IN_CI:
            pytest.fail(why)
        pytest.skip(why)
    from playwright.sync_api import sync_playwright
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


class Page:
    """A page with its console errors and failed requests recorded."""

    def __init__(self, browser, name, hash_="", settle=True):
        self.page = browser.new_page(viewport={"width": 1280, "height": 800})
        self.name = name
        self.errors = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.on("requestfailed", lambda r: self.errors.append(f"request failed: {r.url}"))
        # Navigation committed only: the page then loads and draws on its own, so several pages
        # opened one after another load side by side (open_pages); settle() waits for each.
        self.page.goto((SITE / name).as_uri() + hash_, wait_until="commit")
        if settle:
            self.settle()

    def settle(self):
        """Waits for the page's load event, then (the explorer) its `probelab.ready`, and its
        first picture: what a page opened alone waits for."""
        self.page.wait_for_load_state("load")
        if self.name == "index.html":
            self.page.evaluate("() => probelab.ready")
        self.page.wait_for_function("() => performance.getEntriesByName('first-picture').length > 0")
        return self

    def eval(self, js, arg=None):
        return self.page.evaluate(js, arg)

    def close(self):
        assert self.errors == [], f"console errors or failed requests: {self.errors}"
        self.page.close()


def explorer(browser, map_, domain, encoders):
    return Page(browser, "index.html", f"#map={map_}&domain={domain}&enc={','.join(encoders)}")


def probelab_bin():
    return os.environ.get("PROBELAB_BIN", str(REPO / "target" / "release" / "probelab"))


def open_pages(browser, specs):
    """Pages (name, hash) opened together, each loading as it would alone, then each settled:
    the browser loads them side by side instead of one after another."""
    pages = [Page(browser, name, hash_, settle=False) for name, hash_ in specs]
    return [p.settle() for p in pages]


# The encoders the explorer lists for each (map, domain), read from the page opened on them.
SHOWN = {}
READ_SHOWN = "async ([m, d]) => (await probelab.mapData(m)).domains[d].encoders.map(e => [e.name, e.family, e.form])"


def domain_page(browser, map_, domain):
    """The explorer opened on a map and a domain, its listed encoders recorded in SHOWN."""
    page = Page(browser, "index.html", f"#map={map_}&domain={domain}")
    SHOWN[(map_, domain)] = page.eval(READ_SHOWN, [map_, domain])
    return page


def prefetch_shown(browser, map_, domains):
    """shown_encoders for several domains, their pages opened together."""
    missing = [d for d in domains if (map_, d) not in SHOWN]
    for d, page in zip(missing, open_pages(browser, [("index.html", f"#map={map_}&domain={d}") for d in missing])):
        SHOWN[(map_, d)] = page.eval(READ_SHOWN, [map_, d])
        page.close()


def shown_encoders(browser, map_, domain):
    """The encoders the explorer lists, from a page opened on that map and domain (once per
    module: each such page is loaded, and checked for console errors, the first time)."""
    if (map_, domain) not in SHOWN:
        domain_page(browser, map_, domain).close()
    return SHOWN[(map_, domain)]


def one_per_family(encs, registered):
    seen, out = set(), []
    for name, family, form in encs:
        if name in registered and (family, form) not in seen:
            seen.add((family, form))
            out.append((name, family, form))
    return out


def unit_normals(n, seed, up=None):
    rng = random.Random(seed)
    out = []
    while len(out) < n:
        v = [rng.gauss(0, 1) for _ in range(3)]
        r = math.sqrt(sum(c * c for c in v))
        v = [c / r for c in v]
        if up is None or sum(a * b for a, b in zip(v, up)) > 1e-3:
            out.append(v)
    return out


# The six axes the lightmap experiments declare, as `eval --domain` spells them.
AXES = {"+x": (1.0, 0.0, 0.0), "-x": (-1.0, 0.0, 0.0), "+y": (0.0, 1.0, 0.0),
        "-y": (0.0, -1.0, 0.0), "+z": (0.0, 0.0, 1.0), "-z": (0.0, 0.0, -1.0)}
# The lightmap and occlusion families, shown at every normal (and the SH the page evaluates).
SURFACE_FAMILIES = {"AHD", "HHD", "H-basis", "probe occlusion"}


@pytest.mark.parametrize("domain,normal,families", [("sphere", None, 6), ("hemisphere:+y", AXES["+y"], 8),
                                                    ("hemisphere:-x", AXES["-x"], 5), ("hemisphere:-y", AXES["-y"], 5)])
def test_the_page_evaluates_what_the_library_reconstructs(browser, domain, normal, families):
    import numpy as np
    import probelab
    registered = set(probelab.encoders())
    page = domain_page(browser, MAP, domain)
    chosen = one_per_family(SHOWN[(MAP, domain)], registered)
    assert len({f for _, f, _ in chosen}) >= families, chosen
    for name, family, form in chosen:
        if form == "sh":
            normals = unit_normals(1000, 7, normal)
        else:
            normals = page.eval("(d) => probelab.gridNormals(d)", domain)
        got = np.array(page.eval("async ([m, e, n, d]) => await probelab.evaluate(m, e, n, d)", [MAP, name, normals, domain]))
        want = probelab.irradiance(MAP, name, np.array(normals), normal=normal, root=str(REPO))
        scale = np.abs(want).max()
        err = np.abs(got - want).max() / scale
        assert err <= 1e-4, f"{name} ({family}, {form}) on {domain}: page vs library {err:.2e} of the largest E/pi"
    page.close()


@pytest.mark.parametrize("domain", ["sphere", "hemisphere:+y", "hemisphere:-y", "hemisphere:+z"])
def test_in_page_rmse_is_evals(browser, domain):
    encs = [n for n, _, _ in one_per_family(shown_encoders(browser, MAP, domain), set(_registered()))]
    page = explorer(browser, MAP, domain, encs)
    shown = {s["encoder"]: s for s in page.eval("() => probelab.shown()")}
    page.close()
    out = subprocess.run([probelab_bin(), "--root", str(REPO), "eval", MAP, "--encoders", ",".join(encs), "--domain", domain,
                          "--resolution", "24x12", "--format", "json", "--no-timing"], capture_output=True, text=True, check=True)
    rows = json.loads(out.stdout)["rows"]
    assert len(rows) == len(encs)
    for r in rows:
        s = shown[r["encoder"]]
        assert s["metric"] == r["metric"] == "exact" and s["resolution"] == "24x12" and s["domain"] == domain
        for k in ("rmse", "rel_rmse"):
            assert abs(s[k] - r[k]) <= 1e-3 * abs(r[k]) + 1e-12, f"{r['encoder']} {k}: page {s[k]} vs eval {r[k]}"


def _registered():
    import probelab
    return list(probelab.encoders())


def sphere_pixels(page, encoder, view, kind):
    """The RGB pixels of one drawn sphere inside 90% of its radius. The page sends their bytes
    as one base64 string: Playwright passes an array of arrays item by item (about 1 s for a
    sphere's 9,000 pixels), a string at once."""
    packed = page.eval("""([e, v, k]) => {
        const c = document.querySelector(`canvas[data-encoder="${e}"][data-view="${v}"][data-kind="${k}"]`);
        const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data, r = c.width / 2, out = [];
        for (let y = 0; y < c.height; y++) for (let x = 0; x < c.width; x++) {
          const dx = (x + 0.5 - r) / r, dy = (y + 0.5 - r) / r;
          if (dx * dx + dy * dy < 0.81) { const i = 4 * (y * c.width + x); out.push(String.fromCharCode(d[i], d[i + 1], d[i + 2])); }
        }
        return btoa(out.join('')); }""", [encoder, view, kind])
    raw = base64.b64decode(packed)
    return [list(raw[i:i + 3]) for i in range(0, len(raw), 3)]


def test_a_constant_environment_renders_uniform_spheres_and_a_neutral_error(browser):
    page = explorer(browser, CONSTANT, "sphere", ["sh0", "sh2"])
    for view in ("front", "top"):
        for enc, kind in (("reference", "lit"), ("sh0", "lit"), ("sh2", "lit")):
            px = sphere_pixels(page, enc, view, kind)
            assert len(px) > 1000 and max(max(abs(a - b) for a, b in zip(p, px[0])) for p in px) <= 1, f"{enc} {view} not uniform"
            assert 60 < px[0][1] < 250, f"{enc} {view}: exposure puts the mean at 0.5, got {px[0]}"
        for enc in ("sh0", "sh2"):
            px = sphere_pixels(page, enc, view, "error")
            assert all(max(abs(c - 247) for c in p) <= 1 for p in px), f"{enc} {view}: zero error is not neutral"
    stats = page.eval("() => probelab.shown()")
    assert all(s["rmse"] < 1e-6 for s in stats), stats
    page.close()


def picture_and_numbers(page):
    return page.eval("""() => {
        const pix = Array.from(document.querySelectorAll('canvas.sphere')).map(c => c.toDataURL()).join('');
        return [pix, document.getElementById('spheres').innerText + document.getElementById('tone-note').innerText]; }""")


def test_the_domains_are_the_sphere_and_the_six_axes(browser):
    """Every axis the lightmap experiments declare is a hemisphere: +y with every encoder, the
    other five with the lightmap and occlusion encoders and the SH the page evaluates, each of
    them also shown on +y; every encoder of +y defined only about a surface normal (absent from
    the sphere) is shown at every normal."""
    page = Page(browser, "index.html", f"#map={MAP}")
    domains = page.eval("() => PROBELAB_INDEX.domains.map(d => [d.label, d.normal, d.every_encoder])")
    assert [d[0] for d in domains] == ["sphere"] + [f"hemisphere:{a}" for a in ("+y", "-y", "+x", "-x", "+z", "-z")]
    prefetch_shown(browser, MAP, [d[0] for d in domains])
    for label, normal, every in domains[1:]:
        assert normal == list(AXES[label.split(":")[1]]) and every == (label == "hemisphere:+y")
    floor = {e[0]: e for e in shown_encoders(browser, MAP, "hemisphere:+y")}
    probe = {e[0] for e in shown_encoders(browser, MAP, "sphere")}
    # Defined only about a surface normal: shown on the floor, not on the sphere.
    surface = {n for n, (_, f, _) in floor.items() if f in SURFACE_FAMILIES and n not in probe}
    assert len(surface) >= 10, floor
    for label, _, _ in domains[2:]:
        encs = shown_encoders(browser, MAP, label)
        names = {e[0] for e in encs}
        assert surface <= names, f"{label} lacks {surface - names}"
        assert all(n in floor and (f in SURFACE_FAMILIES or form == "sh") for n, f, form in encs), encs
    page.close()


def test_the_normal_changes_the_picture_and_the_numbers(browser):
    page = explorer(browser, MAP, "hemisphere:+y", ["ahd_search_hemi", "hhd_search_hemi"])
    before = picture_and_numbers(page)
    for label in ("hemisphere:-y", "hemisphere:+x"):
        page.eval("(v) => { const d = document.getElementById('domain'); d.value = v; d.dispatchEvent(new Event('change')); }", label)
        page.page.wait_for_function("(b) => Array.from(document.querySelectorAll('canvas.sphere')).map(c => c.toDataURL()).join('') !== b", arg=before[0], timeout=20000)
        after = picture_and_numbers(page)
        assert after[0] != before[0] and after[1] != before[1], label
        assert {s["domain"] for s in page.eval("() => probelab.shown()")} == {label}
        before = after
    page.close()


def test_every_choice_changes_the_picture_and_the_numbers(browser):
    page = explorer(browser, MAP, "sphere", ["sh1", "sh2"])
    before = picture_and_numbers(page)
    steps = {
        "map": "() => document.querySelector(\"#maps button[data-map='pmndrs_city_256x128']\").click()",
        "encoder": "() => document.querySelector(\"#encoders input[value='sh0']\").click()",
        "exposure": "() => { const e = document.getElementById('exposure'); e.value = 2; e.dispatchEvent(new Event('input')); }",
        "domain": "() => { const d = document.getElementById('domain'); d.value = 'hemisphere:+y'; d.dispatchEvent(new Event('change')); }",
    }
    for what, js in steps.items():
        page.eval(js)
        # One render replaces every sphere and its numbers at once (explorer.js `render`), so the
        # first changed picture comes with its numbers: no settling time to wait out.
        page.page.wait_for_function("(b) => { const c = Array.from(document.querySelectorAll('canvas.sphere')).map(c => c.toDataURL()).join(''); return c !== b; }", arg=before[0], timeout=20000)
        after = picture_and_numbers(page)
        assert after[0] != before[0], f"choosing another {what} left the picture unchanged"
        assert after[1] != before[1], f"choosing another {what} left the numbers unchanged"
        before = after
    page.close()


@pytest.mark.parametrize("name", ["index.html", "claims.html", "landscape.html"])
def test_every_page_fits_1280x800_with_readable_text(browser, name):
    page = Page(browser, name)
    width = page.eval("() => document.documentElement.scrollWidth")
    assert width <= 1280, f"{name}: {width} px wide, scrolls horizontally"
    small = page.eval("""() => { const out = [];
        for (const el of document.querySelectorAll('body *')) {
          const own = Array.from(el.childNodes).some(n => n.nodeType === 3 && n.textContent.trim());
          const s = getComputedStyle(el);
          if (own && s.display !== 'none' && el.offsetParent !== null && parseFloat(s.fontSize) < 12) out.push(el.tagName + ' ' + s.fontSize);
        } return out; }""")
    assert small == [], f"{name}: text under 12 px: {small[:5]}"
    shots = os.environ.get("PROBELAB_SCREENSHOTS")
    if shots:
        page.page.screenshot(path=str(pathlib.Path(shots) / f"viewer_{name.replace('.html', '')}.png"))
    first = page.eval("() => performance.getEntriesByName('first-picture')[0].startTime")
    print(f"{name}: first picture at {first:.0f} ms after navigation start (performance mark 'first-picture')")
    page.close()


def test_the_claims_view_lists_every_claim_with_its_evidence(browser):
    page = Page(browser, "claims.html")
    rows = page.eval("() => document.querySelectorAll('tr.claim').length")
    with open(REPO / "results" / "CLAIMS.csv", encoding="utf-8") as f:
        expected = sum(1 for _ in f) - 1
    assert rows == expected == 22
    page.page.click("tr.claim >> nth=0")
    links = page.eval("() => Array.from(document.querySelectorAll('tr.detail:not([hidden]) a')).map(a => a.getAttribute('href'))")
    evidence = [a for a in links if a.startswith("../claims/") and a.endswith(".md#z1")]
    assert evidence and (SITE.parent / evidence[0][3:].split("#")[0]).is_file(), links
    page.close()


def _declarations():
    import tomllib
    out = {}
    for f in sorted((REPO / "experiments" / "claims").glob("*.toml")):
        paper = tomllib.loads(f.read_text(encoding="utf-8"))
        for c in paper["claim"]:
            out[c["id"]] = (paper, c)
    return out


def test_every_claim_opens_its_figure_and_its_explorer_preset(browser):
    """Each claim's figure is its declared one (else a sheet of its primary check's experiment),
    a committed file; its preset's encoders are ones its checks judge or compare with, its maps
    ones its checks name (a check's maps, its map sets, or for `all` any map), and the link opens
    the explorer on exactly that map, domain and encoders."""
    decl = _declarations()
    page = Page(browser, "claims.html")
    ev = page.eval("() => PROBELAB_CLAIMS.evidence")
    assert set(ev) == set(decl)
    presets = 0
    for cid, e in ev.items():
        paper, c = decl[cid]
        checks = c["check"]
        if "figure" in c:
            # One figure, or a list of them: the claims view opens the first.
            first = c["figure"][0] if isinstance(c["figure"], list) else c["figure"]
            assert e["figure"]["image"] == first["image"]
        if e["figure"]:
            assert (SITE.parent / e["figure"]["image"]).is_file(), (cid, e["figure"])
            tables = [k["table"] for k in checks if not k["table"].startswith("measure:")]
            assert "figure" in c or e["figure"]["image"].split("/")[0] in tables, (cid, e["figure"])
        if e["preset"] is None:
            continue
        presets += 1
        p = e["preset"]
        named = {k["encoder"] for k in checks} | {k["baseline"] for k in checks if "baseline" in k}
        assert p["encoders"] and set(p["encoders"]) <= named, (cid, p)
        assert p["domain"] in ("sphere", "hemisphere:+y"), (cid, p)
        allowed = set()
        for k in checks:
            allowed |= set(k.get("maps", []))
            for on in k.get("on", ["all"]):
                allowed |= set(paper.get("map_sets", {}).get(on, []))
        if not any("maps" not in k and "all" in k.get("on", ["all"]) for k in checks):
            assert set(p["maps"]) <= allowed, (cid, p)
    assert presets >= 10, f"only {presets} claims have an explorer preset"
    hrefs = {}
    for cid, e in ev.items():
        if not e["preset"]:
            continue
        page.page.click(f"#claim-{cid}")
        hrefs[cid] = page.eval(f"() => document.querySelector('#claim-{cid} + tr.detail p.preset a').getAttribute('href')")
    page.close()
    # Each link opened in a fresh page, four at a time side by side (each page also loads every
    # map's data for its thumbnails, so more at once would only add memory).
    cids = list(hrefs)
    for at in range(0, len(cids), 4):
        batch = cids[at:at + 4]
        for cid, ex in zip(batch, open_pages(browser, [("index.html", hrefs[cid][len("index.html"):]) for cid in batch])):
            e = ev[cid]
            first = e["preset"]["maps"][0]
            state = ex.eval("() => probelab.state()")
            assert (state["map"], state["domain"], state["encoders"]) == (first, e["preset"]["domain"], e["preset"]["encoders"]), (cid, state)
            assert [s["encoder"] for s in ex.eval("() => probelab.shown()")] == e["preset"]["encoders"], cid
            ex.close()


def test_the_landscape_marks_a_pareto_front(browser):
    page = Page(browser, "landscape.html")
    data = page.eval("() => probelab.landscape()")
    pts = data["points"]
    assert len(pts) >= 10 and data["front"]
    byname = {p["encoder"]: p for p in pts}
    front = [byname[n] for n in data["front"]]
    # No point is both cheaper (or as cheap) and strictly more accurate than a front point.
    for f in front:
        assert not any(p["scalars"] <= f["scalars"] and p["rel"] < f["rel"] and p is not f for p in pts)
    page.close()


def test_the_site_is_under_10_mb():
    total = sum(p.stat().st_size for p in SITE.rglob("*") if p.is_file())
    print(f"results/site: {total / 1e6:.2f} MB in {sum(1 for p in SITE.rglob('*') if p.is_file())} files")
    assert total < 10e6
