// probelab results viewer: the sphere explorer. Pick a map, a domain and encoders; see the
// reference, each encoding and its signed error as lit spheres (front and top views, drag to
// turn), with the sheets' tone map and diverging map. Evaluation: encodings whose stored form is
// SH irradiance (form "sh") are evaluated here from their coefficients (shader and script);
// the others ship the library's E/pi on the domain's grid (form "grid"), interpolated between
// nodes for the picture. The numbers under a sphere are over the domain's grid.
"use strict";
(function (P) {
  const I = window.PROBELAB_INDEX;
  const SIZE = 120;
  const state = { map: null, domain: "sphere", encoders: [], stops: 0, range: 0.1, yaw: 0, pitch: 0, stats: [] };

  function domainInfo(label) {
    const d = I.domains.find(function (x) { return x.label === label; });
    if (!d) throw new Error("unknown domain " + label + "; the site has " + I.domains.map(function (x) { return x.label; }).join(", "));
    if (!d._normals) {
      const f = P.decodeF32(d.normals);
      d._normals = [];
      for (let i = 0; i < f.length; i += 3) d._normals.push([f[i], f[i + 1], f[i + 2]]);
    }
    return d;
  }

  function entryOf(map, domain, name) {
    const e = map.domains[domain].encoders.find(function (x) { return x.name === name; });
    if (!e) throw new Error("encoder " + name + " is not shown for map " + map.name + " on " + domain);
    if (e.form === "sh" && !e._coeffs) e._coeffs = e.entries.map(function (x) { return x[3]; });
    if (e.form === "grid" && !e._values) e._values = P.decodeDifferences(e.differences, e.scale, referenceOf(map, domain));
    return e;
  }

  function referenceOf(map, domain) {
    const d = map.domains[domain];
    if (!d._reference) d._reference = P.decodeF32(d.reference);
    return d._reference;
  }

  /** Bilinear interpolation of grid values (3 per node) at world normal n; null outside. */
  function sampleGrid(values, dom, n) {
    const f = dom.frame; // row-major: world = F * local, so local = F^T * world
    const lx = f[0] * n[0] + f[3] * n[1] + f[6] * n[2];
    const ly = f[1] * n[0] + f[4] * n[1] + f[7] * n[2];
    const lz = f[2] * n[0] + f[5] * n[1] + f[8] * n[2];
    const W = I.resolution[0], H = I.resolution[1], rows = dom.resolution[1];
    if (rows < H && ly < 0) return null;
    const theta = Math.atan2(lx, -lz), phi = Math.acos(Math.max(-1, Math.min(1, ly)));
    const fx = (theta / (2 * Math.PI) + 0.5) * W - 0.5;
    const fy = Math.min(Math.max((phi / Math.PI) * H - 0.5, 0), rows - 1);
    const x0 = Math.floor(fx), y0 = Math.floor(fy), tx = fx - x0, ty = fy - y0;
    const y1 = Math.min(y0 + 1, rows - 1);
    const at = function (x, y, k) { return values[3 * (y * W + ((x % W) + W) % W) + k]; };
    return [0, 1, 2].map(function (k) {
      return (1 - ty) * ((1 - tx) * at(x0, y0, k) + tx * at(x0 + 1, y0, k)) + ty * ((1 - tx) * at(x0, y1, k) + tx * at(x0 + 1, y1, k));
    });
  }

  function evalEntry(e, dom, n) {
    if (e.form === "sh") {
      const y = P.shBasis(n[0], n[1], n[2]);
      const out = [0, 0, 0];
      e._coeffs.forEach(function (c, i) { out[0] += c[0] * y[i]; out[1] += c[1] * y[i]; out[2] += c[2] * y[i]; });
      return out;
    }
    return sampleGrid(e._values, dom, n);
  }

  /**
   * probelab.evaluate(map, encoder, normals, domain = "sphere"): the page's E/pi of `encoder`
   * fitted to `map` on `domain` at each unit normal [x, y, z] (world, +Y up), as [r, g, b]
   * (null outside a hemisphere). What the spheres show; the tests compare it with the library.
   */
  P.evaluate = async function (map, encoder, normals, domain) {
    const m = await P.mapData(map);
    const dom = domainInfo(domain || "sphere");
    const e = entryOf(m, dom.label, encoder);
    return normals.map(function (n) { return evalEntry(e, dom, n); });
  };

  /** probelab.gridNormals(domain): the normals of the domain's grid (eval --resolution 32x16). */
  P.gridNormals = function (domain) { return domainInfo(domain || "sphere")._normals.slice(); };

  /** The weighted RMSE of E/pi and its ratio to the reference's RMS (reference::metrics::score). */
  P.score = function (ref, test, weights) {
    const se = [0, 0, 0], sr = [0, 0, 0];
    let wsum = 0;
    weights.forEach(function (w, i) {
      for (let k = 0; k < 3; k++) {
        const d = test[3 * i + k] - ref[3 * i + k];
        se[k] += d * d * w; sr[k] += ref[3 * i + k] * ref[3 * i + k] * w;
      }
      wsum += w;
    });
    const rmse = Math.sqrt((se[0] + se[1] + se[2]) / (3 * wsum));
    const rms = Math.sqrt((sr[0] + sr[1] + sr[2]) / (3 * wsum));
    return { rmse: rmse, rel_rmse: rms > 0 ? rmse / rms : (rmse === 0 ? 0 : Infinity) };
  };

  function gridValues(e, dom) {
    if (e.form === "grid") return e._values;
    const out = new Float64Array(dom._normals.length * 3);
    dom._normals.forEach(function (n, i) { const v = evalEntry(e, dom, n); out.set(v, 3 * i); });
    return out;
  }

  /** probelab.shown(): per shown encoding, its map, domain, metric and scores over the grid. */
  P.shown = function () { return state.stats.slice(); };
  /** probelab.state(): the explorer's current choice (map, domain, encoders, exposure, range). */
  P.state = function () { return { map: state.map, domain: state.domain, encoders: state.encoders.slice(), stops: state.stops, range: state.range }; };

  // ---- drawing -------------------------------------------------------------------------------
  const VIEWS = [
    { name: "front", caption: "front: viewer on +Z, +Y up", m: [1, 0, 0, 0, 1, 0, 0, 0, 1] },
    { name: "top", caption: "top: viewer on +Y, -Z up", m: [1, 0, 0, 0, 0, 1, 0, -1, 0] },
  ];

  function mul3(a, b) {
    const o = new Array(9);
    for (let r = 0; r < 3; r++) for (let c = 0; c < 3; c++) o[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
    return o;
  }

  function dragRotation() {
    const cy = Math.cos(state.yaw), sy = Math.sin(state.yaw), cp = Math.cos(state.pitch), sp = Math.sin(state.pitch);
    return mul3([cy, 0, sy, 0, 1, 0, -sy, 0, cy], [1, 0, 0, 0, cp, -sp, 0, sp, cp]);
  }

  function domainStats(map, dom, ref) {
    let ysum = 0, wsum = 0, max = 0;
    dom.weights.forEach(function (w, i) {
      ysum += w * P.luminance([ref[3 * i], ref[3 * i + 1], ref[3 * i + 2]]); wsum += w;
      max = Math.max(max, ref[3 * i], ref[3 * i + 1], ref[3 * i + 2]);
    });
    return { meanY: ysum / wsum, max: max };
  }

  async function render() {
    const map = await P.mapData(state.map);
    const dom = domainInfo(state.domain);
    const ref = referenceOf(map, dom.label);
    const rs = domainStats(map, dom, ref);
    const tone = P.tone(rs.meanY, rs.max, state.stops);
    const floorY = 0.01 * rs.meanY;
    const available = map.domains[dom.label].encoders.map(function (e) { return e.name; });
    const shownEncoders = state.encoders.filter(function (n) { return available.indexOf(n) >= 0; });
    const rot = dragRotation();
    const box = document.getElementById("spheres");
    const frag = document.createDocumentFragment();
    const head = document.createElement("div");
    head.className = "sphere-head";
    head.innerHTML = "<span></span>" + VIEWS.map(function (v) { return "<span>" + v.caption + "<br>lit</span><span>" + v.name + "<br>error</span>"; }).join("");
    frag.appendChild(head);
    const refRow = { label: "reference", sub: "exact E/\u03c0, " + I.resolution.join("\u00d7") + " grid", entry: null };
    const rows = [refRow].concat(shownEncoders.map(function (n) { return { label: n, entry: entryOf(map, dom.label, n) }; }));
    state.stats = [];
    rows.forEach(function (row) {
      const div = document.createElement("div");
      div.className = "sphere-row";
      const label = document.createElement("div");
      label.className = "sphere-label";
      const style = row.entry ? I.styles[row.label] : null;
      label.innerHTML = (style ? P.markerSvg(style) + " " : "") + "<b></b><br><small></small>";
      label.querySelector("b").textContent = row.label;
      let numbers = row.sub || "";
      if (row.entry) {
        const s = P.score(ref, gridValues(row.entry, dom), dom.weights);
        state.stats.push({ map: map.name, domain: dom.label, encoder: row.label, metric: "exact", weighting: "solid-angle", resolution: I.resolution.join("x"), rmse: s.rmse, rel_rmse: s.rel_rmse, form: row.entry.form });
        numbers = "RMSE " + P.sig(s.rmse, 3) + " E/\u03c0, rel. " + P.sig(100 * s.rel_rmse, 3) + "% (solid-angle weighted, " + I.resolution.join("\u00d7") + " grid, " + dom.label + "); " + (row.entry.form === "sh" ? "evaluated here" : "library grid");
      }
      label.querySelector("small").textContent = numbers;
      div.appendChild(label);
      VIEWS.forEach(function (v) {
        const m = mul3(rot, v.m);
        for (const mode of [row.entry ? 1 : 0, 2]) {
          const c = document.createElement("canvas");
          c.width = SIZE; c.height = SIZE;
          c.className = "sphere";
          c.dataset.encoder = row.label; c.dataset.view = v.name; c.dataset.kind = mode === 2 ? "error" : "lit";
          if (mode === 2 && !row.entry) { div.appendChild(document.createElement("span")); continue; }
          P.drawSphere(c, { map: map, dom: dom, ref: ref, entry: row.entry, mode: mode, view: m, tone: tone, floorY: floorY, range: state.range, knots: I.diverging, resolution: I.resolution });
          c.addEventListener("pointerdown", startDrag);
          div.appendChild(c);
        }
      });
      frag.appendChild(div);
    });
    box.replaceChildren(frag);
    drawColourBar();
    document.getElementById("tone-note").textContent = "exposure \u00d7" + P.sig(tone.exposure, 3) + " (reference mean Y \u2192 0.5, then " + (state.stops >= 0 ? "+" : "") + state.stops + " stops), Reinhard white " + P.sig(tone.white, 3) + ", sRGB; E/\u03c0 < 0 black";
    if (!performance.getEntriesByName("first-picture").length) performance.mark("first-picture");
  }

  let drag = null;
  function startDrag(ev) {
    drag = { x: ev.clientX, y: ev.clientY, yaw: state.yaw, pitch: state.pitch };
    ev.preventDefault();
  }
  window.addEventListener("pointermove", function (ev) {
    if (!drag) return;
    state.yaw = drag.yaw + (ev.clientX - drag.x) * 0.01;
    state.pitch = Math.max(-1.5, Math.min(1.5, drag.pitch + (ev.clientY - drag.y) * 0.01));
    schedule();
  });
  window.addEventListener("pointerup", function () { drag = null; });

  let pending = false;
  function schedule() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(function () { pending = false; render().catch(P.fail); });
  }

  function drawColourBar() {
    const c = document.getElementById("colour-bar");
    const ctx = c.getContext("2d");
    for (let x = 0; x < c.width; x++) {
      const rgb = P.diverging(((x + 0.5) / c.width) * 2 - 1, I.diverging);
      ctx.fillStyle = "rgb(" + rgb.join(",") + ")";
      ctx.fillRect(x, 0, 1, c.height);
    }
    const r = 100 * state.range;
    document.getElementById("bar-labels").innerHTML = ["-" + P.sig(r, 2) + "%", "-" + P.sig(r / 2, 2) + "%", "0", "+" + P.sig(r / 2, 2) + "%", "+" + P.sig(r, 2) + "%"].map(function (t) { return "<span>" + t + "</span>"; }).join("");
  }

  // ---- controls ------------------------------------------------------------------------------
  function readHash() {
    // Parsed by hand: URLSearchParams would read the "+" of "hemisphere:+y" as a space.
    const h = new Map(location.hash.slice(1).split("&").filter(Boolean).map(function (kv) {
      const i = kv.indexOf("=");
      return [kv.slice(0, i), decodeURIComponent(kv.slice(i + 1))];
    }));
    if (h.get("map") && I.maps.indexOf(h.get("map")) >= 0) state.map = h.get("map");
    if (h.get("domain")) state.domain = domainInfo(h.get("domain")).label;
    if (h.get("enc")) state.encoders = h.get("enc").split(",").filter(Boolean);
  }

  function writeHash() {
    history.replaceState(null, "", "#map=" + encodeURIComponent(state.map) + "&domain=" + encodeURIComponent(state.domain) + "&enc=" + state.encoders.map(encodeURIComponent).join(","));
  }

  async function showEncoders() {
    const map = await P.mapData(state.map);
    const list = document.getElementById("encoders");
    const encs = map.domains[state.domain].encoders;
    const byFamily = {};
    encs.forEach(function (e) { (byFamily[e.family] = byFamily[e.family] || []).push(e); });
    const frag = document.createDocumentFragment();
    I.families.filter(function (f) { return byFamily[f]; }).forEach(function (f) {
      const g = document.createElement("fieldset");
      g.innerHTML = "<legend></legend>";
      g.querySelector("legend").textContent = f;
      byFamily[f].forEach(function (e) {
        const l = document.createElement("label");
        l.title = e.basis || map.bases[e.name] || "";
        l.innerHTML = "<input type=checkbox> " + P.markerSvg(I.styles[e.name]) + " <span></span> <small></small>";
        l.querySelector("span").textContent = e.name;
        l.querySelector("small").textContent = e.storage + (e.form === "sh" ? "" : " \u00b7 grid");
        const box = l.querySelector("input");
        box.value = e.name;
        box.checked = state.encoders.indexOf(e.name) >= 0;
        box.addEventListener("change", function () {
          state.encoders = box.checked ? state.encoders.concat([e.name]) : state.encoders.filter(function (n) { return n !== e.name; });
          writeHash(); schedule();
        });
        g.appendChild(l);
      });
      frag.appendChild(g);
    });
    list.replaceChildren(frag);
  }

  async function chooseMap(name) {
    state.map = name;
    document.querySelectorAll("#maps button").forEach(function (b) { b.classList.toggle("chosen", b.dataset.map === name); });
    const map = await P.mapData(name);
    const names = map.domains[state.domain].encoders.map(function (e) { return e.name; });
    state.encoders = state.encoders.filter(function (n) { return names.indexOf(n) >= 0; });
    if (!state.encoders.length) state.encoders = names.slice(0, 2);
    await showEncoders();
    writeHash();
    await render();
  }

  function showMaps() {
    const box = document.getElementById("maps");
    for (const name of I.maps) {
      const b = document.createElement("button");
      b.dataset.map = name;
      b.title = name;
      b.innerHTML = "<img alt=''><span></span>";
      b.querySelector("span").textContent = name;
      b.addEventListener("click", function () { chooseMap(name).catch(P.fail); });
      box.appendChild(b);
    }
  }

  /** The thumbnails come with each map's data: loaded after the first picture. */
  async function showThumbnails() {
    const box = document.getElementById("maps");
    for (const name of I.maps) {
      const m = await P.mapData(name);
      box.querySelector("button[data-map='" + name + "'] img").src = m.thumbnail;
    }
  }

  async function start() {
    state.map = I.maps[0];
    readHash();
    const dsel = document.getElementById("domain");
    I.domains.forEach(function (d) {
      const o = document.createElement("option");
      o.value = d.label;
      o.textContent = d.label + (d.normal ? (d.every_encoder ? ": every encoder" : ": lightmap, occlusion and SH encoders") : ": a probe");
      dsel.appendChild(o);
    });
    dsel.value = state.domain;
    dsel.addEventListener("change", function () { state.domain = dsel.value; chooseMap(state.map).catch(P.fail); });
    const ex = document.getElementById("exposure");
    ex.addEventListener("input", function () { state.stops = Number(ex.value); document.getElementById("exposure-value").textContent = (state.stops >= 0 ? "+" : "") + state.stops; schedule(); });
    const er = document.getElementById("range");
    er.addEventListener("input", function () { state.range = Math.pow(10, Number(er.value)); schedule(); });
    state.range = Math.pow(10, Number(er.value));
    showMaps();
    await chooseMap(state.map);
    await showThumbnails();
  }

  P.ready = start().catch(P.fail);
})(window.probelab);
