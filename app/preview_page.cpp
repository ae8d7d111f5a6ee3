// The page follows /events (server-sent events, one JSON snapshot each; see preview_state.h):
// it loads /image?id=N when a new stage is ready, drawing it at the scene's size, shows the
// diagnostics over the last good image while the scene has errors, and progress and statistics.
#include "app/preview_page.h"

namespace wsd::app {

namespace {

constexpr std::string_view kPage = R"WSDPAGE(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>wsd preview</title>
<style>
  body { margin: 0; font: 14px system-ui, sans-serif; background: #1e1e1e; color: #ddd; }
  header { display: flex; gap: 1em; align-items: center; padding: 6px 12px; background: #2b2b2b; }
  header h1 { font-size: 15px; margin: 0; font-weight: 600; }
  #phase { padding: 1px 8px; border-radius: 8px; background: #444; }
  #phase.error { background: #a33; color: #fff; }
  #phase.done { background: #2a6b2a; color: #fff; }
  progress { width: 200px; }
  main { display: flex; gap: 16px; padding: 12px; align-items: flex-start; flex-wrap: wrap; }
  #view { position: relative; display: inline-block; background: #000; min-width: 64px; min-height: 64px; }
  #image { display: block; max-width: 100%; image-rendering: pixelated; }
  #view.coarse #image { image-rendering: auto; }
  #diagnostics { position: absolute; left: 0; right: 0; top: 0; margin: 0; padding: 10px;
                 max-height: 100%; overflow: auto; background: rgba(40, 0, 0, 0.88); color: #fdd;
                 font: 13px ui-monospace, monospace; white-space: pre; }
  #diagnostics[hidden] { display: none; }
  #view.stale #image { opacity: 0.45; }
  table { border-collapse: collapse; font-size: 13px; }
  td { padding: 1px 8px; border-bottom: 1px solid #333; }
  td:last-child { text-align: right; font-variant-numeric: tabular-nums; }
  #files { font-size: 12px; color: #999; }
</style>
</head>
<body>
<header>
  <h1>wsd preview</h1>
  <span id="phase">connecting</span>
  <progress id="progress" max="1" value="0"></progress>
  <span id="stage"></span>
  <span id="connection"></span>
</header>
<main>
  <div id="view">
    <img id="image" alt="">
    <pre id="diagnostics" hidden></pre>
  </div>
  <section>
    <table id="stats"></table>
    <p id="files"></p>
  </section>
</main>
<script>
"use strict";
const $ = (id) => document.getElementById(id);
const image = $("image");
let shownId = 0;
let latest = null;

// What a test or a script can read: the last snapshot and when each image was drawn.
window.wsdPreview = { snapshot: null, loaded: [] };

image.addEventListener("load", () => {
  const id = Number(image.dataset.requested);
  image.dataset.loaded = String(id);
  window.wsdPreview.loaded.push({ id: id, generation: Number(image.dataset.generation),
                                  stage: Number(image.dataset.stage), time: Date.now() });
});

const statRows = [
  ["render_seconds", "render time (s)"], ["parse_seconds", "parse time (s)"],
  ["build_seconds", "build time (s)"], ["mrays_per_second", "Mrays/s"],
  ["camera_rays", "camera rays"], ["shadow_rays", "shadow rays"],
  ["reflection_rays", "reflection rays"], ["refraction_rays", "refraction rays"],
  ["triangle_tests", "triangle tests"], ["sphere_tests", "sphere tests"],
  ["box_tests", "BVH box tests"], ["peak_memory_bytes", "peak memory (MiB)"]];

function showStats(stats) {
  const table = $("stats");
  table.textContent = "";
  if (!stats) return;
  for (const [key, label] of statRows) {
    if (!(key in stats)) continue;
    let value = stats[key];
    if (key === "peak_memory_bytes") value = (value / 1048576).toFixed(1);
    else if (key.endsWith("_seconds") || key === "mrays_per_second") value = Number(value).toPrecision(3);
    else if (typeof value === "number") value = value.toLocaleString("en-US");
    const row = table.insertRow();
    row.insertCell().textContent = label;
    row.insertCell().textContent = value;
  }
  if (stats.effects && stats.effects.length) {
    const row = table.insertRow();
    row.insertCell().textContent = "effects";
    row.insertCell().textContent = stats.effects.join(", ");
  }
}

function show(s) {
  latest = s;
  window.wsdPreview.snapshot = s;
  const phase = $("phase");
  phase.textContent = s.phase;
  phase.className = s.phase;
  $("progress").value = s.progress;
  $("stage").textContent = s.stages ? "stage " + s.stage + "/" + s.stages +
      " (" + s.image_width + "\u00d7" + s.image_height + ")" : "";
  const diagnostics = $("diagnostics");
  diagnostics.textContent = s.diagnostics;
  diagnostics.hidden = s.diagnostics === "";
  const view = $("view");
  view.classList.toggle("stale", s.diagnostics !== "");
  if (s.image_id && s.image_id !== shownId) {
    shownId = s.image_id;
    image.dataset.requested = String(s.image_id);
    image.dataset.generation = String(s.image_generation);
    image.dataset.stage = String(s.stage);
    image.width = s.width;    // a coarse stage is drawn at the scene's size
    image.height = s.height;
    view.classList.toggle("coarse", s.stage < s.stages);
    image.src = "image?id=" + s.image_id;
  }
  showStats(s.stats);
  $("files").textContent = s.files.length ? "watching: " + s.files.join(", ") : "";
}

function connect() {
  const events = new EventSource("events");
  events.onopen = () => { $("connection").textContent = ""; };
  events.onmessage = (e) => show(JSON.parse(e.data));
  events.onerror = () => { $("connection").textContent = "(reconnecting\u2026)"; };
}
connect();
</script>
</body>
</html>
)WSDPAGE";

}  // namespace

std::string_view preview_page_html() {
    return kPage;
}

}  // namespace wsd::app
