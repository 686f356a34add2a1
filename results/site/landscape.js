// probelab results viewer: the cost landscape. Error against stored scalars and against
// evaluation time, one point per encoder (geometric mean of rel. RMSE over the chosen maps),
// coloured and marked by the one style table, with the Pareto front. Chart.js draws it.
"use strict";
(function (P) {
  const D = window.PROBELAB_LANDSCAPE;
  const L = D.rows.map(function (r) { const o = {}; D.columns.forEach(function (c, i) { o[c] = r[i]; }); return o; });
  const I = window.PROBELAB_INDEX;
  const state = { table: null, map: "all", families: {} };
  const charts = {};

  function options(sel, values, label) {
    values.forEach(function (v) { const o = document.createElement("option"); o.value = v; o.textContent = label ? label(v) : v; sel.appendChild(o); });
  }

  /** One point per encoder of the chosen table, maps and families. */
  function points() {
    const by = {};
    L.forEach(function (p) {
      if (p.table !== state.table || !(p.rel_rmse > 0)) return;
      if (state.map !== "all" && p.map !== state.map) return;
      if (!state.families[p.family]) return;
      const b = by[p.encoder] = by[p.encoder] || { encoder: p.encoder, family: p.family, logs: 0, n: 0, maps: {}, scalars: p.stored_scalars, ns: [], rmse: [] };
      b.logs += Math.log(p.rel_rmse); b.n += 1; b.maps[p.map] = true;
      if (p.eval_ns > 0) b.ns.push(p.eval_ns);
      b.rmse.push(p.rmse);
    });
    return Object.values(by).map(function (b) {
      b.ns.sort(function (x, y) { return x - y; });
      return { encoder: b.encoder, family: b.family, rel: Math.exp(b.logs / b.n), maps: Object.keys(b.maps).length, cases: b.n, scalars: b.scalars, ns: b.ns.length ? b.ns[(b.ns.length - 1) >> 1] : null };
    });
  }

  /** The points no other point beats in both cost and error, by cost. */
  function pareto(pts, cost) {
    const sorted = pts.filter(function (p) { return p[cost] > 0; }).sort(function (a, b) { return a[cost] - b[cost] || a.rel - b.rel; });
    const front = [];
    let best = Infinity;
    sorted.forEach(function (p) { if (p.rel < best) { front.push(p); best = p.rel; } });
    return front;
  }

  function draw(id, cost, title) {
    const pts = points().filter(function (p) { return p[cost] > 0; });
    const front = pareto(pts, cost);
    const datasets = pts.map(function (p) {
      const s = I.styles[p.encoder] || { colour: "#888", marker: "circle" };
      return { label: p.encoder, data: [{ x: p[cost], y: p.rel, p: p }], backgroundColor: s.colour, borderColor: "#222", borderWidth: 0.8, pointStyle: P.chartPointStyle(s.marker), pointRadius: front.indexOf(p) >= 0 ? 7 : 5 };
    });
    datasets.push({ label: "Pareto front", type: "line", data: front.map(function (p) { return { x: p[cost], y: p.rel }; }), borderColor: "#333", borderDash: [4, 3], pointRadius: 0, fill: false, stepped: "after" });
    const cfg = {
      type: "scatter",
      data: { datasets: datasets },
      options: {
        animation: false, maintainAspectRatio: false,
        plugins: {
          legend: { display: false },
          title: { display: true, text: title + ", " + (D.resolution[state.table] || "") + " grid", font: { size: 13 } },
          tooltip: { callbacks: { label: function (ctx) {
            const p = ctx.raw.p;
            if (!p) return "Pareto front";
            return p.encoder + " (" + p.family + "): rel. RMSE " + P.sig(100 * p.rel, 3) + "% over " + p.maps + " map(s), " + p.scalars + " scalars, " + (p.ns ? P.sig(p.ns, 3) + " ns/normal" : "no timing");
          } } },
        },
        scales: {
          x: { type: "logarithmic", title: { display: true, text: cost === "scalars" ? "stored scalars per probe or texel" : "evaluation time, ns per normal (median over maps)" }, ticks: { font: { size: 12 } } },
          y: { type: "logarithmic", title: { display: true, text: "relative RMSE of E/\u03c0 (geometric mean over maps)" }, ticks: { font: { size: 12 } } },
        },
      },
    };
    if (charts[id]) charts[id].destroy();
    charts[id] = new Chart(document.getElementById(id), cfg);
  }

  function redraw() {
    draw("by-scalars", "scalars", "error against storage (" + state.table + ")");
    draw("by-time", "ns", "error against evaluation time (" + state.table + ")");
  }

  /** probelab.landscape(): the points drawn, for the tests. */
  P.landscape = function () { return { points: points(), front: pareto(points(), "scalars").map(function (p) { return p.encoder; }) }; };

  const tables = Array.from(new Set(L.map(function (p) { return p.table; })));
  state.table = tables[0];
  const tsel = document.getElementById("table");
  options(tsel, tables);
  const msel = document.getElementById("map");
  function fillMaps() {
    msel.replaceChildren();
    options(msel, ["all"].concat(Array.from(new Set(L.filter(function (p) { return p.table === state.table; }).map(function (p) { return p.map; })))));
    state.map = "all";
  }
  fillMaps();
  tsel.addEventListener("change", function () { state.table = tsel.value; fillMaps(); redraw(); });
  msel.addEventListener("change", function () { state.map = msel.value; redraw(); });
  const fams = document.getElementById("families");
  I.families.filter(function (f) { return L.some(function (p) { return p.family === f; }); }).forEach(function (f) {
    state.families[f] = true;
    const l = document.createElement("label");
    l.innerHTML = "<input type=checkbox checked> <span></span>";
    l.querySelector("span").textContent = f;
    l.querySelector("input").addEventListener("change", function (ev) { state.families[f] = ev.target.checked; redraw(); });
    fams.appendChild(l);
  });
  redraw();
  performance.mark("first-picture");
})(window.probelab);
