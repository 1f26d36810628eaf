// Opens a `ulog report` page in headless Chromium (playwright-core with the system's
// browser) and prints, as one JSON object, what the Rust test (tests/report.rs) checks:
// console errors and requests, each plot's drawn line pixels, the ranges after a zoom,
// the legend's values where the mouse hovers, the messages table's rows, the title and
// the text of every table cell (tests/text_in_documents.rs), the spectra's and step
// responses' line pixels, the spectrograms' coloured cells and the diagnostics table.
//
//   node report_check.js REPORT.html HOVER_PLOT [SCREENSHOT.png]
"use strict";
const { chromium } = require("playwright-core");
const path = require("path");
const os = require("os");
const fs = require("fs");

async function main() {
  const [report, hoverPlot, screenshot] = process.argv.slice(2);
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "ulog-report-chromium-"));
  // An empty profile of its own (playwright passes it as --user-data-dir).
  const browser = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.ULOG_CHROMIUM || "/usr/bin/chromium",
    headless: true,
    viewport: { width: 1280, height: 1000 },
    args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync"],
  });
  const out = { errors: [], requests: [] };
  try {
    const page = await browser.newPage();
    page.on("console", (m) => { if (m.type() === "error") out.errors.push(m.text()); });
    page.on("pageerror", (e) => out.errors.push(String(e)));
    page.on("requestfailed", (r) => out.errors.push("failed request " + r.url()));
    page.on("request", (r) => out.requests.push(r.url()));
    const url = "file://" + path.resolve(report);
    await page.goto(url, { waitUntil: "load" });
    await page.waitForFunction(() => window.ulogReport && window.ulogReport.ready, null,
      { timeout: 20000 });
    out.requests = out.requests.filter((u) => u !== url);
    out.origin_us = await page.evaluate(() =>
      JSON.parse(document.getElementById("report-data").textContent).origin_us);

    // Per plot: coloured pixels (axes, grid and text are grey; no line colour is),
    // at least a quarter opaque, drawn without the flight-mode bands and marks, so
    // that what is counted is lines (overlapping lines mix their colours, which
    // stay coloured).
    out.plots = await page.evaluate(async () => {
      const api = window.ulogReport;
      const frame = () => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
      const count = (plots) => {
        const res = {};
        for (const [id, u] of Object.entries(plots)) {
          const c = u.ctx.canvas;
          const px = u.ctx.getImageData(0, 0, c.width, c.height).data;
          let line = 0;
          for (let i = 0; i < px.length; i += 4) {
            if (px[i + 3] < 64) continue;
            const hi = Math.max(px[i], px[i + 1], px[i + 2]);
            const lo = Math.min(px[i], px[i + 1], px[i + 2]);
            if (hi - lo >= 24) line += 1;
          }
          res[id] = { linePixels: line, series: u.series.length - 1 };
        }
        return res;
      };
      api.plain = true;
      Object.values(api.plots).forEach((u) => u.redraw(false, false));
      await frame();
      // The spectra and step responses (no bands or marks) counted alike.
      const res = { time: count(api.plots), analysis: count(api.analysis || {}) };
      api.plain = false;
      Object.values(api.plots).forEach((u) => u.redraw(false, false));
      await frame();
      return res;
    });
    out.analysis = out.plots.analysis;
    out.plots = out.plots.time;
    // The spectrograms: coloured cells, their columns and bins.
    out.heatmaps = await page.evaluate(() => {
      const res = {};
      for (const [id, m] of Object.entries(window.ulogReport.heatmaps || {})) {
        const c = m.canvas;
        const px = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
        let coloured = 0;
        for (let i = 0; i < px.length; i += 4) {
          const hi = Math.max(px[i], px[i + 1], px[i + 2]);
          const lo = Math.min(px[i], px[i + 1], px[i + 2]);
          if (hi - lo >= 24) coloured += 1;
        }
        res[id] = { colouredPixels: coloured, pixels: c.width * c.height,
          columns: m.columns, bins: m.bins };
      }
      return res;
    });
    out.diagnostics = await page.evaluate(() =>
      Array.from(document.querySelectorAll("#diagnostics tbody tr")).map((tr) =>
        Array.from(tr.querySelectorAll("td")).map((td) => td.textContent)));
    out.track = await page.evaluate(() => {
      const c = document.getElementById("track");
      if (!c) return null;
      const px = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      for (let i = 0; i < px.length; i += 4) {
        if (px[i] === 0x1f && px[i + 1] === 0x77 && px[i + 2] === 0xb4) n += 1;
      }
      return n;
    });

    // Zoom: drag across the middle half of the first plot.
    const ids = Object.keys(out.plots);
    const first = ids[0];
    const over = async (id) => {
      const el = await page.$("#plot-" + id + " .u-over");
      await el.scrollIntoViewIfNeeded();
      return el.boundingBox();
    };
    const ranges = () => page.evaluate(() => {
      const r = {};
      for (const [id, u] of Object.entries(window.ulogReport.plots)) {
        r[id] = [u.scales.x.min, u.scales.x.max];
      }
      return r;
    });
    out.before = await ranges();
    const b = await over(first);
    const y = b.y + b.height / 2;
    await page.mouse.move(b.x + b.width * 0.25, y);
    await page.mouse.down();
    await page.mouse.move(b.x + b.width * 0.5, y, { steps: 5 });
    await page.mouse.move(b.x + b.width * 0.75, y, { steps: 5 });
    await page.mouse.up();
    out.zoomed = first;
    out.after = await ranges();
    // Double-click: every plot back to the whole log.
    await page.mouse.dblclick(b.x + b.width * 0.5, y);
    out.reset = await ranges();

    // Hover the middle of one plot; read its legend.
    if (hoverPlot && out.plots[hoverPlot]) {
      const h = await over(hoverPlot);
      await page.mouse.move(h.x + h.width * 0.5, h.y + h.height / 2, { steps: 3 });
      out.hover = await page.evaluate((id) => {
        const rows = document.querySelectorAll("#plot-" + id + " .u-legend tr.u-series");
        return Array.from(rows).map((tr) => [
          tr.querySelector(".u-label").textContent,
          tr.querySelector(".u-value").textContent,
        ]);
      }, hoverPlot);
    }

    // The information tables as a reader sees them: each row's visible text (a folded
    // text shows its summary only), its folds, and the bytes its download link gives.
    out.information = await page.evaluate(async () => {
      const rows = document.querySelectorAll("#info tbody tr, #multi-info tbody tr");
      const res = [];
      for (const tr of rows) {
        const [key, value] = tr.querySelectorAll("td");
        const link = value.querySelector("a[download]");
        let bytes = null;
        if (link) {
          const buf = await (await fetch(link.href)).arrayBuffer();
          bytes = Array.from(new Uint8Array(buf));
        }
        res.push({
          key: key.textContent,
          visible: value.innerText,
          folds: Array.from(value.querySelectorAll("details")).map((d) => ({
            open: d.open,
            summary: d.querySelector("summary").innerText,
            text: d.querySelector("pre").textContent,
          })),
          download: link ? link.download : null,
          bytes,
        });
      }
      return res;
    });

    out.messages = await page.evaluate(() =>
      document.querySelectorAll("#messages tbody tr").length);
    // The page's title and every table cell's text, as the browser read them.
    out.title = await page.title();
    out.cells = await page.evaluate(() =>
      Array.from(document.querySelectorAll("td")).map((td) => td.textContent));
    // The level filter: ERROR and above (a page comparing logs has no messages).
    const filter = await page.$("#level-filter");
    if (filter) {
      await page.selectOption("#level-filter", "3");
      out.messagesShownAtError = await page.evaluate(() =>
        Array.from(document.querySelectorAll("#messages tbody tr")).filter((tr) => !tr.hidden).length);
    }
    out.paramsAcross = await page.evaluate(() =>
      Array.from(document.querySelectorAll("#params-across tbody tr")).map((tr) =>
        Array.from(tr.querySelectorAll("td")).map((td) => td.textContent)));

    if (screenshot) {
      if (filter) await page.selectOption("#level-filter", "7");
      await page.evaluate(() => window.scrollTo(0, 0));
      await page.mouse.move(0, 0);
      await page.setViewportSize({ width: 1280, height: 1500 });
      await page.waitForTimeout(300);
      await page.screenshot({ path: screenshot });
      const analysis = await page.$("#analysis-section");
      if (analysis) {
        await analysis.screenshot({ path: screenshot.replace(/\.png$/, "") + "-analysis.png" });
      }
    }
    // `data:` URLs hold their bytes (the download links fetched above): no request
    // leaves the page.
    out.requests = out.requests.filter((u) => !u.startsWith("data:"));
  } finally {
    await browser.close();
    fs.rmSync(profile, { recursive: true, force: true });
  }
  process.stdout.write(JSON.stringify(out) + "\n");
}

main().catch((e) => {
  process.stderr.write(String(e && e.stack || e) + "\n");
  process.exit(1);
});
