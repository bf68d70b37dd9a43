#include "report/html_report.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "export/glsl.h"
#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::string Number(const Json& v) {
  if (v.is_number()) return text_util::FormatNumber(v.get<double>(), 6);
  if (v.is_string()) return HtmlEscape(v.get<std::string>());
  if (v.is_array()) {
    std::string s;
    for (const Json& e : v) s += (s.empty() ? "" : ", ") + Number(e);
    return "[" + s + "]";
  }
  return HtmlEscape(v.dump());
}

// The figures drawn into a temporary folder and read back as data: URLs.
std::string FigureSections(const ReportInput& input,
                           std::vector<std::string>* notes, double* exposure) {
  char pattern[] = "/tmp/clothfit-report-XXXXXX";
  const char* dir = mkdtemp(pattern);
  if (!dir) throw InputError("report: cannot create a temporary folder");
  const fs::path folder(dir);
  std::ostringstream html;
  try {
    const std::string& label = input.label;
    const WrittenFigures written =
        WriteFitFigures(input.model.params, label, input.table, kFigureNames,
                        input.options, [&](const std::string& name) {
                          return (folder / (name + ".png")).string();
                        });
    if (notes) *notes = written.notes;
    for (const auto& [name, path] : written.files) {
      html << "<figure id=\"figure-" << name << "\"><img alt=\"" << name
           << "\" src=\"data:image/png;base64," << Base64(ReadBytes(path))
           << "\"><figcaption>" << name << ".png</figcaption></figure>\n";
    }
    for (const std::string& note : written.notes) {
      html << "<p class=\"note\">" << HtmlEscape(note) << "</p>\n";
    }
    SphereFigure(input.model.params, label, input.options.sphere_pixels,
                 exposure);
  } catch (...) {
    fs::remove_all(folder);
    throw;
  }
  fs::remove_all(folder);
  return html.str();
}

std::string FitTables(const std::string& fit_json) {
  if (fit_json.empty()) {
    return "<p>The parameter file has no \"fit\" object (not a fit's "
           "result): no summary or standard deviations.</p>\n";
  }
  const Json fit = Json::parse(fit_json);
  std::ostringstream html;
  html << "<h2>Fit summary</h2>\n<table id=\"fit-summary\">\n";
  for (const char* key :
       {"usable", "converged", "termination", "message", "rms", "relative_rms",
        "final_cost", "iterations", "rows", "rows_not_used", "starts"}) {
    if (fit.contains(key)) {
      html << "<tr><th>" << key << "</th><td>" << Number(fit[key])
           << "</td></tr>\n";
    }
  }
  for (const char* key : {"at_bound", "fixed", "identifiability"}) {
    if (fit.contains(key) && !fit[key].empty()) {
      html << "<tr><th>" << key << "</th><td>" << Number(fit[key])
           << "</td></tr>\n";
    }
  }
  html << "</table>\n";
  if (fit.contains("values")) {
    html << "<h2>Fitted parameters</h2>\n<table id=\"fit-parameters\">\n"
            "<tr><th>parameter</th><th>value</th><th>standard deviation</th>"
            "<th></th></tr>\n";
    for (const auto& [name, value] : fit["values"].items()) {
      const Json* sd = fit.contains("stddev") && fit["stddev"].contains(name)
                           ? &fit["stddev"][name]
                           : nullptr;
      std::string flag;
      for (const char* list : {"at_bound", "fixed"}) {
        if (fit.contains(list)) {
          for (const Json& n : fit[list]) {
            if (n == name) flag = list;
          }
        }
      }
      html << "<tr><td>" << HtmlEscape(name) << "</td><td>" << Number(value)
           << "</td><td>" << (sd ? Number(*sd) : "-") << "</td><td>" << flag
           << "</td></tr>\n";
    }
    html << "</table>\n";
  }
  if (fit.contains("selection") && fit["selection"].contains("candidates")) {
    const Json& s = fit["selection"];
    html << "<h2>Model selection</h2>\n<p>chosen: "
         << Number(s.value("chosen", Json(""))) << "; "
         << Number(s.value("reason", Json(""))) << "</p>\n"
         << "<table id=\"selection\">\n<tr><th>candidate</th><th>free "
            "parameters</th><th>relative rms</th><th>held-out relative "
            "rms</th><th>BIC</th><th>usable</th><th>note</th></tr>\n";
    for (const Json& c : s["candidates"]) {
      html << "<tr><td>" << Number(c.value("description", Json("")))
           << "</td><td>" << Number(c.value("free_parameters", Json("-")))
           << "</td><td>" << Number(c.value("relative_rms", Json("-")))
           << "</td><td>" << Number(c.value("heldout_relative_rms", Json("-")))
           << "</td><td>" << Number(c.value("bic", Json("-"))) << "</td><td>"
           << Number(c.value("usable", Json("-"))) << "</td><td>"
           << Number(c.value("note", Json(""))) << "</td></tr>\n";
    }
    html << "</table>\n";
  }
  return html.str();
}

// Every entry of the parameter file but "fit".
std::string ParameterFileTable(const ParamFile& file) {
  const Json j = Json::parse(FormatParamFile(file));
  std::ostringstream html;
  html << "<h2>Parameter file</h2>\n<table id=\"parameters\">\n";
  for (const auto& [key, value] : j.items()) {
    if (key == "fit") continue;
    html << "<tr><th>" << HtmlEscape(key) << "</th><td>" << Number(value)
         << "</td></tr>\n";
  }
  html << "</table>\n";
  return html.str();
}

// Shader and script of the interactive sphere: the model's clothfit_rho
// on the sphere of render/sphere.h (the same normal frame, the view +z,
// radiance rho(wi, wo) for unit irradiance, the PNG's exposure and sRGB).
std::string SphereSection(const ModelParams& model, double exposure) {
  std::string glsl;
  try {
    glsl = GlslSource(model);
  } catch (const InputError& e) {
    return "<p class=\"note\">No interactive sphere: " + HtmlEscape(e.what()) +
           "</p>\n<pre id=\"status\">OK no GLSL form</pre>\n";
  }
  // A script element's text is not decoded: the GLSL goes in as it is
  // (GLSL has no '<' followed by '/').
  std::ostringstream html;
  html
      << R"(<div id="sphere-box"><canvas id="sphere" width="256" height="256"></canvas>
<p>Drag on the sphere to move the light (the point under the cursor faces it).
Radiance rho(wi, wo) under one directional light of unit irradiance, the
model's GLSL from <code>clothfit export --format glsl</code>, exposure )"
      << text_util::FormatNumber(exposure, 4)
      << R"( (as sphere.png), sRGB.</p></div>
<pre id="status">loading</pre>
<script id="glsl" type="x-shader/x-fragment">)"
      << glsl << R"(
uniform vec3 u_light;
uniform float u_exposure;
uniform float u_size;
out vec4 clothfit_colour;
vec3 ToSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055,
             step(0.0031308, c));
}
void main() {
  vec2 p = gl_FragCoord.xy * 2.0 / u_size - 1.0;
  float r2 = dot(p, p);
  if (r2 >= 1.0) { clothfit_colour = vec4(vec3(128.0 / 255.0), 1.0); return; }
  vec3 n = vec3(p, sqrt(1.0 - r2));
  vec3 b = cross(n, vec3(1.0, 0.0, 0.0));
  b = length(b) > 1e-12 ? normalize(b) : vec3(0.0, 1.0, 0.0);
  vec3 t = cross(b, n);
  vec3 wi = vec3(dot(u_light, t), dot(u_light, b), dot(u_light, n));
  vec3 wo = vec3(t.z, b.z, n.z);
  vec3 radiance = wi.z > 0.0 ? clothfit_rho(wi, wo) : vec3(0.0);
  clothfit_colour = vec4(ToSrgb(radiance * u_exposure), 1.0);
}
</script>
<script>
(function () {
  const status = document.getElementById('status');
  window.addEventListener('error', (e) => { status.textContent = 'ERROR ' + e.message; });
  const canvas = document.getElementById('sphere');
  const gl = canvas.getContext('webgl2');
  if (!gl) { status.textContent = 'ERROR no WebGL 2'; return; }
  function compile(type, text) {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  const fragment = document.getElementById('glsl').textContent;
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER,
      '#version 300 es\nin vec2 a;\nvoid main() { gl_Position = vec4(a, 0.0, 1.0); }\n'));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, fragment));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  gl.useProgram(program);
  const buffer = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
  const a = gl.getAttribLocation(program, 'a');
  gl.enableVertexAttribArray(a);
  gl.vertexAttribPointer(a, 2, gl.FLOAT, false, 0, 0);
  gl.uniform1f(gl.getUniformLocation(program, 'u_exposure'), )"
      << text_util::FormatNumber(exposure, 17) << R"();
  gl.uniform1f(gl.getUniformLocation(program, 'u_size'), canvas.width);
  const lightAt = gl.getUniformLocation(program, 'u_light');
  function draw(light) {
    gl.uniform3fv(lightAt, light);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const e = gl.getError();
    status.textContent = e === gl.NO_ERROR ? 'OK light ' + light.map((v) => v.toFixed(3)).join(' ')
                                           : 'ERROR WebGL error ' + e;
  }
  draw([)"
      << kSphereLight.x << ", " << kSphereLight.y << ", " << kSphereLight.z
      << R"(]);
  let dragging = false;
  function move(event) {
    if (!dragging) return;
    const r = canvas.getBoundingClientRect();
    const x = ((event.clientX - r.left) / r.width) * 2 - 1;
    const y = 1 - ((event.clientY - r.top) / r.height) * 2;
    const d = x * x + y * y;
    if (d >= 1) return;
    draw([x, y, Math.sqrt(1 - d)]);
  }
  canvas.addEventListener('pointerdown', (e) => { dragging = true; move(e); });
  canvas.addEventListener('pointermove', move);
  window.addEventListener('pointerup', () => { dragging = false; });
})();
</script>
)";
  return html.str();
}

}  // namespace

std::string Base64(const std::string& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    unsigned v = 0;
    for (size_t k = 0; k < 3; ++k) {
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    }
    for (size_t k = 0; k < 4; ++k) {
      out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
    }
  }
  return out;
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string ReportHtml(const ReportInput& input,
                       std::vector<std::string>* notes) {
  double exposure = 1.0;
  const std::string figures = FigureSections(input, notes, &exposure);
  const std::string& title = input.label;
  std::ostringstream html;
  html << R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>clothfit report: )"
       << HtmlEscape(title) << R"(</title>
<style>
body { font-family: sans-serif; margin: 0; padding: 0 16px 16px 0; }
#sphere-box { display: flex; gap: 16px; align-items: flex-start; }
#sphere { display: block; cursor: crosshair; touch-action: none; }
table { border-collapse: collapse; margin-bottom: 12px; }
th, td { border: 1px solid #ccc; padding: 2px 8px; text-align: left; }
figure { margin: 12px 0; } img { max-width: 100%; }
.note { color: #a33; }
</style></head><body>
)" << SphereSection(input.model.params, exposure)
       << "<div style=\"padding-left: 16px\">\n<h1>" << HtmlEscape(title)
       << "</h1>\n<p>model: " << ModelName(input.model.params);
  if (input.table) {
    html << "; table: " << input.table->rows.size() << " rows of "
         << QuantityName(input.table->quantity);
  }
  html << "</p>\n"
       << FitTables(input.model.fit_json) << ParameterFileTable(input.model)
       << "<h2>Figures</h2>\n"
       << figures << "</div>\n</body></html>\n";
  return html.str();
}

}  // namespace clothfit
