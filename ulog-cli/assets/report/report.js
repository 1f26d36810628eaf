// The plots of a `ulog report` page, drawn with uPlot from the JSON the page holds:
// time plots with flight-mode bands and marks, zoom linked across plots, the track,
// the spectra and step responses (their own x axes), the spectrograms (a canvas of
// coloured cells), and the level filter of the messages table.
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("report-data").textContent);
  // Line colours: none of them grey, as the axes and grid are.
  var COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
    "#e377c2", "#17becf", "#393b79", "#bcbd22"];
  // The lines of one log on a page comparing logs: solid, dashed, dotted, dash-dot.
  var DASHES = [[], [6, 3], [2, 2], [8, 3, 2, 3]];
  // Apart from the line colours, so that tests can tell lines from marks.
  var MARK_COLORS = { arm: "#006400", disarm: "#444444", takeoff: "#0000cd",
    landing: "#8b008b", error: "#ff0000", diagnostic: "#b8860b" };
  var plots = [];
  // The plots whose x axis is not the log's time: not zoomed with the others.
  var others = [];
  // For tests and the curious: the uPlot instances, by plot id; `plain` leaves the
  // bands and marks out of the next redraw (a test counts the lines' own pixels).
  var api = { plots: {}, analysis: {}, heatmaps: {}, ready: false, plain: false };
  window.ulogReport = api;
  var syncing = false;

  function modeColor(mode, alpha) {
    return "hsla(" + ((mode * 67) % 360) + ",70%,55%," + alpha + ")";
  }

  // Flight modes and marks behind the lines, so that dense marks never hide data.
  function backdrop() {
    return {
      hooks: {
        drawClear: function (u) {
          if (api.plain) return;
          var ctx = u.ctx, b = u.bbox, dpr = window.devicePixelRatio || 1;
          ctx.save();
          data.modes.forEach(function (m) {
            var x0 = Math.max(u.valToPos(m.t0, "x", true), b.left);
            var x1 = Math.min(u.valToPos(m.t1, "x", true), b.left + b.width);
            if (x1 > x0) {
              ctx.fillStyle = modeColor(m.mode, 0.16);
              ctx.fillRect(x0, b.top, x1 - x0, b.height);
            }
          });
          ctx.lineWidth = dpr;
          ctx.font = (10 * dpr) + "px sans-serif";
          // A label closer than 60 px to the previous one goes a line lower; below
          // four lines it is left out (the mark's line stays).
          var lastX = -Infinity, row = 0;
          data.marks.forEach(function (m) {
            var x = u.valToPos(m.t, "x", true);
            if (x < b.left || x > b.left + b.width) return;
            ctx.strokeStyle = MARK_COLORS[m.kind] || "#000";
            ctx.setLineDash(m.kind === "error" ? [2 * dpr, 2 * dpr] : []);
            ctx.beginPath();
            ctx.moveTo(x, b.top);
            ctx.lineTo(x, b.top + b.height);
            ctx.stroke();
            if (m.kind === "error") return;
            if (x - lastX < 60 * dpr) {
              row += 1;
              if (row > 3) return;
            } else {
              row = 0;
              lastX = x;
            }
            ctx.fillStyle = ctx.strokeStyle;
            // Left of the line where the text would run past the plot's right edge.
            var w = ctx.measureText(m.text).width;
            var tx = x + 2 * dpr + w > b.left + b.width ? x - 2 * dpr - w : x + 2 * dpr;
            ctx.fillText(m.text, tx, b.top + (10 + 11 * row) * dpr);
          });
          ctx.restore();
        }
      }
    };
  }

  function zoomAll(min, max) {
    syncing = true;
    plots.forEach(function (u) { u.setScale("x", { min: min, max: max }); });
    syncing = false;
  }

  function plotWidth() {
    return Math.max(320, document.getElementById("plots").clientWidth - 8);
  }

  function valueText(u, v) {
    return v == null ? "—" : String(v);
  }

  function timeText(u, v) {
    return v == null ? "—" : v.toFixed(6) + " s";
  }

  // A tenth of the span above and below, so that lines at the extremes stay inside
  // the plot; a constant line gets ±1 (or ±10 %) around it.
  function yRange(u, min, max) {
    if (min == null || max == null) return [0, 1];
    if (min === max) {
      var d = Math.max(Math.abs(min) * 0.1, 1);
      return [min - d, max + d];
    }
    var pad = (max - min) * 0.1;
    return [min - pad, max + pad];
  }

  function addPlot(p) {
    var box = document.createElement("section");
    box.className = "plot";
    box.id = "plot-" + p.id;
    var h = document.createElement("h2");
    h.textContent = p.title + (p.unit ? " [" + p.unit + "]" : "");
    box.appendChild(h);
    var cap = document.createElement("p");
    cap.className = "source";
    var thinned = p.tables.some(function (t) { return t.thinned; });
    cap.textContent = "from " + p.sources.join(", ") +
      (thinned ? " (thinned: lowest, highest, first and last per 1/2000 of the log)" : "");
    box.appendChild(cap);
    document.getElementById("plots").appendChild(box);

    var tables = p.tables.map(function (t) { return [t.x].concat(t.y); });
    var aligned = tables.length === 1 ? tables[0] : uPlot.join(tables);
    var series = [{ label: "time", value: timeText }];
    var n = 0;
    p.tables.forEach(function (t) {
      t.labels.forEach(function (label, k) {
        // A table with a colour of its own (a log's, comparing logs): its lines
        // differ by dashes.
        var color = t.color || COLORS[n % COLORS.length];
        series.push({
          label: label,
          stroke: color,
          dash: t.color ? DASHES[k % DASHES.length] : undefined,
          width: 1,
          spanGaps: tables.length > 1,
          // A few samples (one, even) are dots as well as a line.
          points: { show: t.x.length < 50, size: 5, stroke: color, fill: color },
          value: valueText
        });
        n += 1;
      });
    });
    var opts = {
      width: plotWidth(),
      height: 260,
      series: series,
      scales: { x: { time: false }, y: { range: yRange } },
      axes: [{ label: data.x_label }, { label: p.unit, size: 60 }],
      cursor: {
        sync: { key: "ulog-report", setSeries: false },
        drag: { x: true, y: false },
        bind: {
          dblclick: function () {
            return function () { zoomAll(extent[0], extent[1]); return null; };
          }
        }
      },
      plugins: [backdrop()],
      hooks: {
        setScale: [function (u, key) {
          if (key !== "x" || syncing) return;
          zoomAll(u.scales.x.min, u.scales.x.max);
        }]
      }
    };
    var u = new uPlot(opts, aligned, box);
    plots.push(u);
    api.plots[p.id] = u;
  }

  function modesLegend() {
    var seen = {};
    var el = document.getElementById("modes");
    data.modes.forEach(function (m) {
      if (seen[m.mode]) return;
      seen[m.mode] = true;
      var s = document.createElement("span");
      s.className = "mode";
      s.style.background = modeColor(m.mode, 0.35);
      s.textContent = m.name;
      el.appendChild(s);
    });
    if (data.modes.length) {
      el.insertBefore(document.createTextNode("Flight modes: "), el.firstChild);
    }
  }

  function niceStep(span) {
    var raw = span / 6, p = Math.pow(10, Math.floor(Math.log10(raw)));
    var k = raw / p;
    return p * (k < 1.5 ? 1 : k < 3.5 ? 2 : k < 7.5 ? 5 : 10);
  }

  // The track, east right and north up, with one metre the same length both ways.
  function drawTrack() {
    var sec = document.getElementById("track-section");
    var h = document.createElement("h2");
    h.textContent = "Track (local position, metres from the estimator's origin)";
    sec.appendChild(h);
    if (!data.track) {
      var note = document.createElement("p");
      note.className = "note";
      note.textContent = "No track: the log has no valid vehicle_local_position.";
      sec.appendChild(note);
      return;
    }
    var size = Math.min(plotWidth(), 640), dpr = window.devicePixelRatio || 1;
    var c = document.createElement("canvas");
    c.id = "track";
    c.width = size * dpr;
    c.height = size * dpr;
    c.style.width = size + "px";
    c.style.height = size + "px";
    sec.appendChild(c);
    var ctx = c.getContext("2d");
    ctx.scale(dpr, dpr);
    var pts = data.track, minE = Infinity, maxE = -Infinity, minN = Infinity, maxN = -Infinity;
    pts.forEach(function (p) {
      minE = Math.min(minE, p[0]); maxE = Math.max(maxE, p[0]);
      minN = Math.min(minN, p[1]); maxN = Math.max(maxN, p[1]);
    });
    var pad = 40, span = Math.max(maxE - minE, maxN - minN, 1);
    var k = (size - 2 * pad) / span;
    var cE = (minE + maxE) / 2, cN = (minN + maxN) / 2;
    function px(e) { return size / 2 + (e - cE) * k; }
    function py(n) { return size / 2 - (n - cN) * k; }
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, size, size);
    var step = niceStep(span);
    ctx.strokeStyle = "#e4e4e4";
    ctx.fillStyle = "#666";
    ctx.font = "10px sans-serif";
    var half = span / 2 + pad / k;
    for (var g = Math.ceil((cE - half) / step) * step; g <= cE + half; g += step) {
      ctx.beginPath(); ctx.moveTo(px(g), 0); ctx.lineTo(px(g), size); ctx.stroke();
      ctx.fillText(g.toFixed(0), px(g) + 2, size - 4);
    }
    for (g = Math.ceil((cN - half) / step) * step; g <= cN + half; g += step) {
      ctx.beginPath(); ctx.moveTo(0, py(g)); ctx.lineTo(size, py(g)); ctx.stroke();
      ctx.fillText(g.toFixed(0), 2, py(g) - 2);
    }
    ctx.strokeStyle = "#1f77b4";
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    pts.forEach(function (p, i) {
      if (i === 0) ctx.moveTo(px(p[0]), py(p[1])); else ctx.lineTo(px(p[0]), py(p[1]));
    });
    ctx.stroke();
    [[pts[0], "#2ca02c", "start"], [pts[pts.length - 1], "#d62728", "end"]].forEach(function (s) {
      ctx.fillStyle = s[1];
      ctx.beginPath();
      ctx.arc(px(s[0][0]), py(s[0][1]), 4, 0, 2 * Math.PI);
      ctx.fill();
      ctx.fillText(s[2], px(s[0][0]) + 6, py(s[0][1]) - 6);
    });
    ctx.fillStyle = "#333";
    ctx.fillText("east [m] →, north [m] ↑", size - 130, 12);
  }

  // A spectrum or step response: x is frequency or time after the step, not the
  // log's time, so it zooms on its own.
  function addXyPlot(p) {
    var box = document.createElement("section");
    box.className = "plot";
    box.id = "analysis-" + p.id;
    var h = document.createElement("h3");
    h.textContent = p.title + (p.unit ? " [" + p.unit + "]" : "");
    box.appendChild(h);
    document.getElementById("analysis-plots").appendChild(box);
    var series = [{ label: p.x_unit, value: valueText }];
    var columns = [p.x];
    p.lines.forEach(function (l, i) {
      var color = COLORS[i % COLORS.length];
      series.push({ label: l[0], stroke: color, width: 1, value: valueText });
      columns.push(l[1]);
    });
    var y = p.log_y ? { distr: 3 } : { range: yRange };
    var u = new uPlot({
      width: plotWidth(),
      height: 260,
      series: series,
      scales: { x: { time: false }, y: y },
      axes: [{ label: p.x_unit === "Hz" ? "frequency [Hz]" : "seconds after the step" },
        { label: p.unit, size: 70, values: p.log_y ? powerTicks : undefined }],
      cursor: { drag: { x: true, y: false } }
    }, columns, box);
    others.push(u);
    api.analysis[p.id] = u;
  }

  // Ticks of a log axis as powers of ten (uPlot's default writes 1e-5 as "0").
  function powerTicks(u, ticks) {
    return ticks.map(function (v) { return v == null ? "" : v.toExponential(0); });
  }

  // A colour from blue (low) through green to yellow (high), for a value in 0..1.
  function heatColor(f) {
    var hue = 240 - 180 * f;
    return "hsl(" + hue + ",85%," + (25 + 40 * f) + "%)";
  }

  // A spectrogram: one column of cells per time, frequency upwards, power as colour
  // between the 2nd and the 99.5th percentile of its cells.
  function addHeatmap(m) {
    var box = document.createElement("section");
    box.className = "plot heatmap";
    box.id = "heatmap-" + m.id;
    var h = document.createElement("h3");
    h.textContent = m.title;
    box.appendChild(h);
    var canvas = document.createElement("canvas");
    var dpr = window.devicePixelRatio || 1;
    var width = plotWidth(), height = 260;
    canvas.width = width * dpr;
    canvas.height = height * dpr;
    canvas.style.width = width + "px";
    canvas.style.height = height + "px";
    box.appendChild(canvas);
    var cap = document.createElement("p");
    cap.className = "source";
    box.appendChild(cap);
    document.getElementById("analysis-plots").appendChild(box);
    var cells = [];
    m.db.forEach(function (c) { c.forEach(function (v) { if (v != null) cells.push(v); }); });
    cells.sort(function (a, b) { return a - b; });
    var lo = cells[Math.floor(cells.length * 0.02)] || 0;
    var hi = cells[Math.min(cells.length - 1, Math.floor(cells.length * 0.995))] || 1;
    if (!(hi > lo)) hi = lo + 1;
    var ctx = canvas.getContext("2d");
    var left = 60 * dpr, bottom = 30 * dpr, top = 8 * dpr, right = 8 * dpr;
    var w = canvas.width - left - right, hgt = canvas.height - top - bottom;
    var t0 = m.t.length ? m.t[0] : 0;
    var t1 = m.t.length ? m.t[m.t.length - 1] + m.width_s : 1;
    var span = Math.max(t1 - t0, 1e-9);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    m.db.forEach(function (c, i) {
      var x0 = left + (m.t[i] - t0) / span * w;
      var cw = Math.max(m.width_s / span * w, 1);
      var bh = hgt / c.length;
      c.forEach(function (v, k) {
        if (v == null) return;
        var f = Math.min(1, Math.max(0, (v - lo) / (hi - lo)));
        ctx.fillStyle = heatColor(f);
        ctx.fillRect(x0, top + hgt - (k + 1) * bh, cw + 0.5, bh + 0.5);
      });
    });
    ctx.fillStyle = "#444";
    ctx.font = (10 * dpr) + "px sans-serif";
    for (var k = 0; k <= 4; k++) {
      var y = top + hgt - k / 4 * hgt;
      ctx.fillText((m.max_hz * k / 4).toFixed(0) + " Hz", 4 * dpr, y + 3 * dpr);
    }
    for (var j = 0; j <= 4; j++) {
      var x = left + j / 4 * w;
      ctx.fillText((t0 + span * j / 4).toFixed(1) + " s", x - 12 * dpr, canvas.height - 10 * dpr);
    }
    cap.textContent = "colour: " + lo.toFixed(0) + " dB (blue) to " + hi.toFixed(0) +
      " dB (yellow); " + m.t.length + " columns of " + m.width_s.toFixed(2) + " s while armed";
    api.heatmaps[m.id] = { canvas: canvas, columns: m.t.length, bins: m.db.length ? m.db[0].length : 0 };
  }

  function levelFilter() {
    var sel = document.getElementById("level-filter");
    if (!sel) return;
    sel.addEventListener("change", function () {
      var max = Number(sel.value);
      document.querySelectorAll("#messages tbody tr").forEach(function (tr) {
        tr.hidden = Number(tr.getAttribute("data-level")) > max;
      });
    });
  }

  // The whole view: the log's duration, widened to any data before or after it, or
  // narrowed to the data where it fills only a sliver of it.
  var extent = (function () {
    var lo = Infinity, hi = -Infinity;
    data.plots.forEach(function (p) {
      p.tables.forEach(function (t) {
        lo = Math.min(lo, t.x[0]);
        hi = Math.max(hi, t.x[t.x.length - 1]);
      });
    });
    if (!(hi > lo)) return [0, Math.max(data.duration, 1e-6)];
    return [lo, hi];
  })();
  api.extent = extent;

  modesLegend();
  data.plots.forEach(addPlot);
  zoomAll(extent[0], extent[1]);
  (data.analysis || []).forEach(addXyPlot);
  (data.heatmaps || []).forEach(addHeatmap);
  drawTrack();
  levelFilter();
  var resizing = null;
  window.addEventListener("resize", function () {
    clearTimeout(resizing);
    resizing = setTimeout(function () {
      var w = plotWidth();
      plots.concat(others).forEach(function (u) { u.setSize({ width: w, height: 260 }); });
    }, 100);
  });
  api.ready = true;
})();
