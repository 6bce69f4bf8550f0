// shadelab report: sortable tables and the method/reference viewer. The page is complete
// without this script; it only adds behaviour. No libraries, nothing fetched.
(function () {
  "use strict";

  // Sort key of a cell: data-v holds a number ("" for n/a; "Infinity", "NaN" parse), else text.
  function key(cell) {
    var v = cell.getAttribute("data-v");
    if (v === null) return { text: cell.textContent.trim().toLowerCase() };
    if (v === "") return { missing: true };
    var x = Number(v);
    return isNaN(x) ? { missing: true, nan: true } : { num: x };
  }

  // n/a and NaN go last in both directions; numbers before text.
  function compare(a, b, dir) {
    if (a.missing || b.missing) return (a.missing ? 1 : 0) - (b.missing ? 1 : 0);
    var r;
    if (a.num !== undefined && b.num !== undefined) r = a.num < b.num ? -1 : a.num > b.num ? 1 : 0;
    else if (a.num !== undefined) r = -1;
    else if (b.num !== undefined) r = 1;
    else r = a.text < b.text ? -1 : a.text > b.text ? 1 : 0;
    return r * dir;
  }

  function sortBy(table, col, th) {
    var dir = th.getAttribute("aria-sort") === "ascending" ? -1 : 1;
    var heads = table.tHead.rows[table.tHead.rows.length - 1].cells;
    for (var i = 0; i < heads.length; i++) heads[i].removeAttribute("aria-sort");
    th.setAttribute("aria-sort", dir === 1 ? "ascending" : "descending");
    var body = table.tBodies[0];
    var rows = Array.prototype.slice.call(body.rows);
    var keyed = rows.map(function (r, i) { return { row: r, k: key(r.cells[col]), i: i }; });
    keyed.sort(function (a, b) { return compare(a.k, b.k, dir) || a.i - b.i; });
    keyed.forEach(function (e) { body.appendChild(e.row); });
  }

  function sortable(table) {
    var heads = table.tHead.rows[table.tHead.rows.length - 1].cells;
    Array.prototype.forEach.call(heads, function (th, col) {
      var b = document.createElement("button");
      b.type = "button";
      b.textContent = th.textContent;
      b.title = "sort by " + th.textContent;
      th.textContent = "";
      th.appendChild(b);
      b.addEventListener("click", function () { sortBy(table, col, th); });
    });
  }

  // Method over reference in one stage: the method shows left of the slider, the reference
  // right of it; "flip" swaps between all-method and all-reference; zoom keeps the centre.
  function viewer(v) {
    var ref = v.querySelector("img.v-ref"), mth = v.querySelector("img.v-mth");
    if (!ref || !mth) return;
    var w = ref.naturalWidth || Number(ref.getAttribute("width")) || 256;
    var h = ref.naturalHeight || Number(ref.getAttribute("height")) || 256;
    var controls = document.createElement("div");
    controls.className = "controls";
    var slider = document.createElement("input");
    slider.type = "range"; slider.min = "0"; slider.max = "100"; slider.value = "50";
    slider.setAttribute("aria-label", "method (left) against reference (right)");
    var flip = document.createElement("button");
    flip.type = "button"; flip.textContent = "flip";
    var zoom = document.createElement("select");
    zoom.setAttribute("aria-label", "zoom");
    [1, 2, 4, 8, 16].forEach(function (z) {
      var o = document.createElement("option");
      o.value = String(z); o.textContent = z + "\u00d7";
      zoom.appendChild(o);
    });
    var label = document.createElement("span");
    label.textContent = "method \u2190 | \u2192 reference";
    controls.append(slider, label, flip, zoom);
    var stage = document.createElement("div");
    stage.className = "stage";
    var layer = document.createElement("div");
    layer.className = "layer";
    stage.appendChild(layer);
    layer.append(ref, mth);
    function setZoom(z) {
      var cx = (stage.scrollLeft + stage.clientWidth / 2) / (layer.offsetWidth || 1);
      var cy = (stage.scrollTop + stage.clientHeight / 2) / (layer.offsetHeight || 1);
      layer.style.width = w * z + "px";
      layer.style.height = h * z + "px";
      stage.scrollLeft = cx * w * z - stage.clientWidth / 2;
      stage.scrollTop = cy * h * z - stage.clientHeight / 2;
    }
    function setSplit(p) { mth.style.clipPath = "inset(0 " + (100 - p) + "% 0 0)"; }
    slider.addEventListener("input", function () { setSplit(Number(slider.value)); });
    flip.addEventListener("click", function () {
      slider.value = Number(slider.value) > 50 ? "0" : "100";
      setSplit(Number(slider.value));
    });
    zoom.addEventListener("change", function () { setZoom(Number(zoom.value)); });
    v.classList.add("js");
    v.append(controls, stage);
    setZoom(1);
    setSplit(50);
  }

  function init() {
    Array.prototype.forEach.call(document.querySelectorAll("table.sortable"), sortable);
    Array.prototype.forEach.call(document.querySelectorAll(".viewer"), viewer);
    document.documentElement.setAttribute("data-report-js", "ready");
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", init);
  else init();
})();
