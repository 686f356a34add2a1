// probelab results viewer: drawing. Spheres in raw WebGL2 (one shared offscreen context, each
// sphere copied to its own canvas), markers as inline SVG, Chart.js point styles for the
// landscape. The tone map and diverging map are the static sheets' (report::tone).
"use strict";
(function (P) {
  const VERT = `#version 300 es
in vec2 corner; out vec2 p;
void main() { p = corner; gl_Position = vec4(corner, 0.0, 1.0); }`;

  const FRAG = `#version 300 es
precision highp float;
precision highp sampler2D;
in vec2 p; out vec4 o;
uniform mat3 view;      // sphere-local (x right, y up, z to the viewer) to world
uniform mat3 toGrid;    // world to the grid's frame (pole +Y)
uniform int W; uniform int H; uniform int rows;
uniform sampler2D refTex; uniform sampler2D testTex;
uniform int form;       // 0: SH irradiance from coeffs, 1: grid (testTex)
uniform vec3 coeffs[25];
uniform int mode;       // 0: reference lit, 1: encoding lit, 2: signed error
uniform float exposure; uniform float white; uniform float floorY; uniform float range;
uniform vec3 knots[9];
const float PI = 3.141592653589793;

vec3 fetchAt(sampler2D t, int x, int y) { return texelFetch(t, ivec2((x + W) % W, y), 0).rgb; }

vec3 grid(sampler2D t, vec3 n) {
  vec3 l = toGrid * n;
  float theta = atan(l.x, -l.z);
  float phi = acos(clamp(l.y, -1.0, 1.0));
  float fx = (theta / (2.0 * PI) + 0.5) * float(W) - 0.5;
  float fy = clamp(phi / PI * float(H) - 0.5, 0.0, float(rows - 1));
  int x0 = int(floor(fx)); int y0 = int(floor(fy));
  float tx = fx - floor(fx); float ty = fy - floor(fy);
  int y1 = min(y0 + 1, rows - 1);
  return mix(mix(fetchAt(t, x0, y0), fetchAt(t, x0 + 1, y0), tx), mix(fetchAt(t, x0, y1), fetchAt(t, x0 + 1, y1), tx), ty);
}

// SH irradiance through band 4: the recurrence of src/math/sh4.rs.
vec3 sh(vec3 n) {
  float cm[5]; float sm[5];
  cm[0] = 1.0; sm[0] = 0.0;
  for (int m = 1; m < 5; m++) { cm[m] = cm[m - 1] * n.x - sm[m - 1] * n.y; sm[m] = sm[m - 1] * n.x + cm[m - 1] * n.y; }
  vec3 acc = vec3(0.0);
  for (int m = 0; m < 5; m++) {
    float pmm = 1.0;
    for (int k = 0; k < m; k++) pmm *= -float(2 * k + 1);
    float pPrev = 0.0; float pl = pmm;
    for (int l = m; l < 5; l++) {
      if (l == m + 1) { pPrev = pl; pl = n.z * float(2 * m + 1) * pmm; }
      else if (l > m + 1) { float nx = (float(2 * l - 1) * n.z * pl - float(l + m - 1) * pPrev) / float(l - m); pPrev = pl; pl = nx; }
      float ratio = 1.0;
      for (int v = l - m + 1; v <= l + m; v++) ratio *= float(v);
      float k = sqrt(float(2 * l + 1) / (4.0 * PI) / ratio);
      int c = l * l + l;
      if (m == 0) acc += coeffs[c] * (k * pl);
      else { float s2 = sqrt(2.0) * k * pl; acc += coeffs[c + m] * (s2 * cm[m]) + coeffs[c - m] * (s2 * sm[m]); }
    }
  }
  return acc;
}

float srgb(float x) { x = clamp(x, 0.0, 1.0); return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055; }
float curve(float v) { float x = max(v * exposure, 0.0); return min(x * (1.0 + x / (white * white)) / (1.0 + x), 1.0); }
vec3 diverging(float v) {
  v = clamp(v, -1.0, 1.0);
  float s = (v + 1.0) * 4.0; int i = min(int(floor(s)), 7); float f = s - float(i);
  return (knots[i] + (knots[i + 1] - knots[i]) * f) / 255.0;
}

void main() {
  float r2 = dot(p, p);
  if (r2 > 1.0) { o = vec4(1.0); return; }
  vec3 n = normalize(view * vec3(p, sqrt(1.0 - r2)));
  if (rows < H && (toGrid * n).y < 0.0) { o = vec4(vec3(0.8), 1.0); return; }
  vec3 ref = grid(refTex, n);
  vec3 test = form == 0 ? sh(n) : grid(testTex, n);
  if (mode == 2) {
    float yr = dot(ref, vec3(0.2126, 0.7152, 0.0722)); float yt = dot(test, vec3(0.2126, 0.7152, 0.0722));
    float den = max(yr, floorY);
    float rel = den > 0.0 ? (yt - yr) / den : 0.0;
    o = vec4(diverging(rel / range), 1.0);
    return;
  }
  vec3 c = mode == 0 ? ref : test;
  o = vec4(srgb(curve(c.r)), srgb(curve(c.g)), srgb(curve(c.b)), 1.0);
}`;

  let gl = null, prog = null, glCanvas = null;
  const textures = new WeakMap();

  function setup(size) {
    glCanvas = document.createElement("canvas");
    glCanvas.width = size; glCanvas.height = size;
    gl = glCanvas.getContext("webgl2", { preserveDrawingBuffer: true, antialias: false });
    if (!gl) throw new Error("this browser has no WebGL2: the spheres cannot be drawn");
    const sh = function (type, src) {
      const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error("shader: " + gl.getShaderInfoLog(s));
      return s;
    };
    prog = gl.createProgram();
    gl.attachShader(prog, sh(gl.VERTEX_SHADER, VERT)); gl.attachShader(prog, sh(gl.FRAGMENT_SHADER, FRAG));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error("program: " + gl.getProgramInfoLog(prog));
    const buf = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 1, -1, -1, 1, 1, 1]), gl.STATIC_DRAW);
    const loc = gl.getAttribLocation(prog, "corner");
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
  }

  function texture(values, w, h) {
    let t = textures.get(values);
    if (t) return t;
    t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB32F, w, h, 0, gl.RGB, gl.FLOAT, values instanceof Float32Array ? values : new Float32Array(values));
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    textures.set(values, t);
    return t;
  }

  /** Draws one sphere into `canvas` (see the fragment shader for the modes). */
  P.drawSphere = function (canvas, o) {
    if (!gl) setup(canvas.width);
    gl.viewport(0, 0, glCanvas.width, glCanvas.height);
    gl.useProgram(prog);
    const u = function (name) { return gl.getUniformLocation(prog, name); };
    const W = o.resolution[0], H = o.resolution[1], rows = o.dom.resolution[1];
    gl.uniformMatrix3fv(u("view"), true, o.view);
    gl.uniformMatrix3fv(u("toGrid"), false, o.dom.frame); // row-major F read column-major is F^T
    gl.uniform1i(u("W"), W); gl.uniform1i(u("H"), H); gl.uniform1i(u("rows"), rows);
    gl.activeTexture(gl.TEXTURE0); gl.bindTexture(gl.TEXTURE_2D, texture(o.ref, W, rows)); gl.uniform1i(u("refTex"), 0);
    const e = o.entry;
    const grid = e && e.form === "grid";
    gl.activeTexture(gl.TEXTURE1); gl.bindTexture(gl.TEXTURE_2D, texture(grid ? e._values : o.ref, W, rows)); gl.uniform1i(u("testTex"), 1);
    gl.uniform1i(u("form"), e && e.form === "sh" ? 0 : 1);
    const c = new Float32Array(75);
    if (e && e.form === "sh") e._coeffs.forEach(function (v, i) { c.set(v, 3 * i); });
    gl.uniform3fv(u("coeffs"), c);
    gl.uniform1i(u("mode"), o.mode);
    gl.uniform1f(u("exposure"), o.tone.exposure); gl.uniform1f(u("white"), o.tone.white);
    gl.uniform1f(u("floorY"), o.floorY); gl.uniform1f(u("range"), o.range);
    gl.uniform3fv(u("knots"), new Float32Array([].concat.apply([], o.knots)));
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    canvas.getContext("2d").drawImage(glCanvas, 0, 0);
  };

  /** A 12 px inline SVG of an encoder's marker in its colour (report::style). */
  P.markerSvg = function (style) {
    if (!style) return "";
    const f = style.colour, s = 'fill="' + f + '" stroke="#222" stroke-width="0.8"';
    const shapes = {
      "circle": '<circle cx="6" cy="6" r="4.5" ' + s + "/>",
      "square": '<rect x="2" y="2" width="8" height="8" ' + s + "/>",
      "triangle-up": '<polygon points="6,1.5 10.5,10 1.5,10" ' + s + "/>",
      "triangle-down": '<polygon points="1.5,2 10.5,2 6,10.5" ' + s + "/>",
      "diamond": '<polygon points="6,1 11,6 6,11 1,6" ' + s + "/>",
      "cross": '<path d="M2,2 L10,10 M10,2 L2,10" stroke="' + f + '" stroke-width="2.5"/>',
      "plus": '<path d="M6,1 L6,11 M1,6 L11,6" stroke="' + f + '" stroke-width="2.5"/>',
      "star": '<polygon points="6,1 7.4,4.5 11,4.6 8.2,6.9 9.1,10.5 6,8.5 2.9,10.5 3.8,6.9 1,4.6 4.6,4.5" ' + s + "/>",
    };
    return '<svg class="marker" width="12" height="12" viewBox="0 0 12 12" aria-hidden="true">' + (shapes[style.marker] || shapes.circle) + "</svg>";
  };

  /** The Chart.js point style of a marker name. */
  P.chartPointStyle = function (marker) {
    return { "circle": "circle", "square": "rect", "triangle-up": "triangle", "triangle-down": "triangle", "diamond": "rectRot", "cross": "crossRot", "plus": "cross", "star": "star" }[marker] || "circle";
  };
})(window.probelab);
