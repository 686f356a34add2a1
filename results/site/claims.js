// probelab results viewer: the claims at a glance (results/CLAIMS.csv as the engine wrote it).
"use strict";
(function (P) {
  const C = window.PROBELAB_CLAIMS;

  function verdictClass(v) {
    if (/^holds/.test(v)) return "verdict-holds";
    if (/^fails/.test(v)) return "verdict-fails";
    return "verdict-other";
  }

  /** The explorer address of a preset on one of its maps. */
  function presetHref(preset, map) {
    return "index.html#map=" + encodeURIComponent(map) + "&domain=" + encodeURIComponent(preset.domain) + "&enc=" + preset.encoders.map(encodeURIComponent).join(",");
  }

  function para(text) {
    const p = document.createElement("p");
    p.textContent = text;
    return p;
  }

  /** The claim's evidence (its declaration, through the report): figure and explorer preset. */
  function evidenceParts(claim) {
    const ev = (C.evidence || {})[claim.id] || {};
    const parts = [];
    if (ev.quote) parts.push(para("The paper: \u201c" + ev.quote + "\u201d"));
    if (ev.preset) {
      const p = para("Open in the explorer (" + ev.preset.encoders.join(", ") + " on " + ev.preset.domain + "): ");
      p.className = "preset";
      ev.preset.maps.forEach(function (m) {
        const a = document.createElement("a");
        a.href = presetHref(ev.preset, m);
        a.textContent = m;
        p.append(a, " ");
      });
      parts.push(p);
    }
    if (ev.figure) {
      const f = document.createElement("figure");
      const a = document.createElement("a");
      a.href = "../" + ev.figure.image;
      const img = document.createElement("img");
      img.src = "../" + ev.figure.image;
      img.alt = "results/" + ev.figure.image;
      img.loading = "lazy";
      a.appendChild(img);
      const cap = document.createElement("figcaption");
      cap.textContent = "results/" + ev.figure.image + ": " + ev.figure.caption;
      f.append(a, cap);
      parts.push(f);
    }
    return parts;
  }

  function detailRow(claim) {
    const tr = document.createElement("tr");
    tr.className = "detail";
    tr.hidden = true;
    const td = document.createElement("td");
    td.colSpan = 5;
    const ev = document.createElement("p");
    const a = document.createElement("a");
    a.href = "../" + claim.detail;
    a.textContent = "Evidence: results/" + claim.detail;
    ev.appendChild(a);
    td.append(para("Criterion: " + claim.criterion), para("Maps: " + claim.maps + "."));
    td.append.apply(td, evidenceParts(claim));
    td.appendChild(ev);
    tr.appendChild(td);
    return tr;
  }

  const body = document.querySelector("#claims tbody");
  C.claims.forEach(function (claim) {
    const tr = document.createElement("tr");
    tr.className = "claim";
    tr.id = "claim-" + claim.id;
    ["id", "kind", "verdict", "paper_figure", "our_figure"].forEach(function (k) {
      const td = document.createElement("td");
      td.textContent = claim[k];
      if (k === "verdict") td.className = verdictClass(claim[k]);
      tr.appendChild(td);
    });
    const detail = detailRow(claim);
    tr.addEventListener("click", function () { detail.hidden = !detail.hidden; });
    body.append(tr, detail);
  });
  if (location.hash.startsWith("#claim-")) {
    const row = document.getElementById(location.hash.slice(1));
    if (row) row.click();
  }
  performance.mark("first-picture");
})(window.probelab);
