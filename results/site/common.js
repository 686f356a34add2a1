// probelab results viewer: what every page shares. The data arrive as scripts
// (window.PROBELAB_INDEX, PROBELAB_MAPS[name], PROBELAB_CLAIMS, PROBELAB_LANDSCAPE), written by
// `probelab report`; a page opened from file:// may not fetch. Irradiance is E/pi throughout.
"use strict";
window.probelab = window.probelab || {};
(function (P) {
  /** A base64 string of little-endian float32 values as a Float32Array. */
  P.decodeF32 = function (b64) {
    const bin = atob(b64);
    const u8 = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) u8[i] = bin.charCodeAt(i);
    return new Float32Array(u8.buffer);
  };

  /**
   * A grid encoding's E/pi from its data (report::site::encode::i16_difference_base64): the
   * reference (Float32Array) plus each little-endian int16 step of `b64` times `scale`.
   */
  P.decodeDifferences = function (b64, scale, reference) {
    const bin = atob(b64);
    const u8 = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) u8[i] = bin.charCodeAt(i);
    const q = new Int16Array(u8.buffer);
    const out = new Float32Array(q.length);
    for (let i = 0; i < q.length; i++) out[i] = reference[i] + q[i] * scale;
    return out;
  };

  /** The file name the report gives a name (report::names::file_safe). */
  P.fileSafe = function (s) {
    return s.replace(/[^A-Za-z0-9._-]/g, "_");
  };

  /** Loads a script once (data travel as scripts, never fetch). */
  const loading = {};
  P.loadScript = function (src) {
    if (!loading[src]) {
      loading[src] = new Promise(function (resolve, reject) {
        const s = document.createElement("script");
        s.src = src;
        s.onload = resolve;
        s.onerror = function () { reject(new Error("cannot load " + src)); };
        document.head.appendChild(s);
      });
    }
    return loading[src];
  };

  /** A map's data (PROBELAB_MAPS[name]), loaded on first use. */
  P.mapData = async function (name) {
    const maps = window.PROBELAB_MAPS || {};
    if (!maps[name]) await P.loadScript("data/map_" + P.fileSafe(name) + ".js");
    const m = window.PROBELAB_MAPS && window.PROBELAB_MAPS[name];
    if (!m) throw new Error("no data for map " + name);
    return m;
  };

  /**
   * The 25 real SH basis functions at unit direction (x, y, z), index l*l + l + m, zonal axis z,
   * Condon-Shortley phase: the recurrence of src/math/sh4.rs (bands 0-2 equal FORMULAS section 2).
   */
  P.shBasis = function (x, y, z) {
    const cm = [1, 0, 0, 0, 0], sm = [0, 0, 0, 0, 0];
    for (let m = 1; m < 5; m++) {
      cm[m] = cm[m - 1] * x - sm[m - 1] * y;
      sm[m] = sm[m - 1] * x + cm[m - 1] * y;
    }
    const out = new Float64Array(25);
    for (let m = 0; m < 5; m++) {
      let pmm = 1;
      for (let k = 0; k < m; k++) pmm *= -(2 * k + 1);
      let pPrev = 0, p = pmm;
      for (let l = m; l < 5; l++) {
        if (l === m + 1) { pPrev = p; p = z * (2 * m + 1) * pmm; }
        else if (l > m + 1) {
          const next = ((2 * l - 1) * z * p - (l + m - 1) * pPrev) / (l - m);
          pPrev = p; p = next;
        }
        let ratio = 1;
        for (let v = l - m + 1; v <= l + m; v++) ratio *= v;
        const k = Math.sqrt((2 * l + 1) / (4 * Math.PI) / ratio);
        const c = l * l + l;
        if (m === 0) out[c] = k * p;
        else { const s2 = Math.SQRT2 * k * p; out[c + m] = s2 * cm[m]; out[c - m] = s2 * sm[m]; }
      }
    }
    return out;
  };

  /** Rec.709 luminance (math::colour). */
  P.luminance = function (c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; };

  /** The sRGB transfer curve of a linear value in [0, 1] (report::tone::srgb_encode). */
  P.srgb = function (x) {
    x = Math.min(Math.max(x, 0), 1);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055;
  };

  /**
   * The sheets' tone (report::tone::Tone::from_reference): exposure puts the reference's mean
   * luminance at 0.5, times 2^stops from the slider; extended Reinhard with white at the
   * reference's largest exposed value.
   */
  P.tone = function (meanY, maxValue, stops) {
    const base = meanY > 0 && isFinite(meanY) ? 0.5 / meanY : 1;
    const exposure = base * Math.pow(2, stops || 0);
    const white = Math.max(maxValue * base, 1);
    return { exposure: exposure, white: isFinite(white) ? white : 1 };
  };

  /** The diverging map (report::tone::diverging) at v in [-1, 1], from its nine knots. */
  P.diverging = function (v, knots) {
    v = isFinite(v) ? Math.min(Math.max(v, -1), 1) : 0;
    const s = (v + 1) * 4, i = Math.min(Math.floor(s), 7), f = s - i;
    return [0, 1, 2].map(function (k) { return Math.round(knots[i][k] + (knots[i + 1][k] - knots[i][k]) * f); });
  };

  /** A number to `digits` significant digits, as the report prints it. */
  P.sig = function (v, digits) {
    if (v === null || v === undefined || !isFinite(v)) return "-";
    if (v === 0) return "0";
    return Number(v.toPrecision(digits || 3)).toString();
  };

  /** Shows an error on the page (and in the console, which the tests watch). */
  P.fail = function (e) {
    const box = document.getElementById("error");
    if (box) { box.textContent = String(e); box.hidden = false; }
    console.error(e);
  };
})(window.probelab);
