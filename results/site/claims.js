// probelab results viewer: the claims at a glance (results/CLAIMS.csv as the engine wrote it).
"use strict";
(function (P) {
  const C = window.PROBELAB_CLAIMS;
  const I = window.PROBELAB_INDEX;

  function verdictClass(v) {
    if (/^holds/.test(v)) return "verdict-holds";
    if (/^fails/.test(v)) return "verdict-fails";
    return "verdict-other";
  }

  /** The explorer links for the maps a claim names (those the site has). */
  function explorerLinks(claim) {
    const named = I.maps.filter(function (m) { return claim.maps.indexOf(m) >= 0 || claim.maps.indexOf(m.replace(/_256x128$/, "")) >= 0; });
    return named.map(function (m) { return '<a href="index.html#map=' + encodeURIComponent(m) + '"></a>'; });
  }

  function detailRow(claim) {
    const tr = document.createElement("tr");
    tr.className = "detail";
    tr.hidden = true;
    const td = document.createElement("td");
    td.colSpan = 5;
    const crit = document.createElement("p");
    crit.textContent = "Criterion: " + claim.criterion;
    const maps = document.createElement("p");
    maps.textContent = "Maps: " + claim.maps + ". ";
    const links = explorerLinks(claim);
    if (links.length) {
      const span = document.createElement("span");
      span.innerHTML = "Open in the explorer: " + links.join(" ");
      span.querySelectorAll("a").forEach(function (a) { a.textContent = decodeURIComponent(a.getAttribute("href").split("=")[1]); });
      maps.appendChild(span);
    }
    const ev = document.createElement("p");
    const a = document.createElement("a");
    a.href = "../" + claim.detail;
    a.textContent = "Evidence: results/" + claim.detail;
    ev.appendChild(a);
    td.append(crit, maps, ev);
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
