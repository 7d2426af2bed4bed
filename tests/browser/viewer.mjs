// The replay viewer in a real browser: Debian's chromium, headless, driven by playwright-core.
//
//   node tests/browser/viewer.mjs PAGE.html RUN.json SCREENSHOT.png [PAGE.html RUN.json SCREENSHOT.png ...]
//
// For each page: loads it from file:// (no server, no network), fails on any console error or
// uncaught exception, plays it to the end through the page's own API (window.cimax), checks
// that the LEDs drawn on the canvas (pixels at the robots' centres) equal the LEDs of the
// run's `--json` report, and saves a screenshot. RUN.json `-` (`cimax swarm run`, which has
// no --json) compares with the verdict the page was written with instead. Exit code 1 on any
// failure, 2 on bad usage or a missing browser.
import { chromium } from "playwright-core";
import { existsSync, readFileSync } from "node:fs";
import { resolve } from "node:path";
import { pathToFileURL } from "node:url";

const BROWSER = process.env.CHROMIUM || "/usr/bin/chromium";
const args = process.argv.slice(2);
if (args.length === 0 || args.length % 3 !== 0) {
  console.error("usage: node viewer.mjs PAGE.html RUN.json SCREENSHOT.png [...]");
  process.exit(2);
}
if (!existsSync(BROWSER)) {
  console.error(`${BROWSER}: no chromium (apt-get install chromium, or set CHROMIUM)`);
  process.exit(2);
}

const browser = await chromium.launch({
  executablePath: BROWSER,
  // As measured on this kind of machine: without the networking flags chromium tries to
  // reach Google at every start.
  args: [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
  ],
});
let failed = 0;
try {
  for (let k = 0; k < args.length; k += 3) {
    const [html, json, shot] = args.slice(k, k + 3);
    const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
    const errors = [];
    page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
    page.on("pageerror", (e) => errors.push(String(e)));
    // Nothing leaves the page: any request but the file itself is an error.
    await page.route("**/*", (route) => {
      const url = route.request().url();
      if (url.startsWith("file:")) return route.continue();
      errors.push(`request to ${url}`);
      return route.abort();
    });
    await page.goto(pathToFileURL(resolve(html)).href);
    await page.waitForFunction(() => window.cimax !== undefined, null, { timeout: 30000 });
    // A failing run opens where it went wrong (the replay's open_at_ms), a passing one at 0.
    const opened = await page.evaluate(() => ({
      at: window.cimax.time(),
      want: JSON.parse(document.getElementById("replay").textContent).open_at_ms,
    }));
    // A failing run's page as it opens, beside the screenshot at the end.
    if (opened.want > 0) await page.screenshot({ path: shot.replace(/\.png$/, "-open.png"), fullPage: true });
    const expected = json === "-"
      ? await page.evaluate(() => JSON.parse(document.getElementById("replay").textContent).header.verdict.leds)
      : JSON.parse(readFileSync(json, "utf8")).runs[0].leds;
    const loaded = await page.evaluate(() => performance.now());
    const t0 = Date.now();
    await page.evaluate(() => window.cimax.playToEnd(10000));
    const wall = (Date.now() - t0) / 1000;
    const end = await page.evaluate(() => ({
      time: window.cimax.time(), duration: window.cimax.duration,
      drawn: window.cimax.ledsDrawn(), state: window.cimax.leds(),
      stats: window.cimax.drawStats(),
    }));
    // Smoothness, reported (not judged: timings depend on the machine): two seconds of play
    // at 1000x from the start.
    const smooth = await page.evaluate(async () => {
      const c = window.cimax, before = c.drawStats();
      c.seek(0); c.play(1000);
      await new Promise((r) => setTimeout(r, 2000));
      c.pause();
      const after = c.drawStats(), frames = after.frames - before.frames;
      const ms = (after.mean_ms * after.frames - before.mean_ms * before.frames) / Math.max(frames, 1);
      c.seek(c.duration);
      return { fps: frames / 2, ms };
    });
    // Click the first robot: its panel must fill in.
    await page.evaluate(() => window.cimax.select(0));
    const panel = await page.textContent("#robot");
    await page.screenshot({ path: shot, fullPage: true });
    const problems = [...errors];
    if (opened.at !== opened.want) problems.push(`opened at ${opened.at} ms, not at ${opened.want} ms`);
    if (end.time < end.duration) problems.push(`stopped at ${end.time} of ${end.duration} ms`);
    if (end.drawn !== expected) problems.push(`LEDs drawn ${end.drawn}, the run's JSON says ${expected}`);
    if (end.state !== expected) problems.push(`LED state ${end.state}, the run's JSON says ${expected}`);
    if (!/robot 0: id \d+, tag \d+/.test(panel)) problems.push(`robot panel: ${panel}`);
    const s = end.stats;
    const name = `${html} (opened at ${(opened.at / 1000).toFixed(1)} s; loaded in ${(loaded / 1000).toFixed(1)} s; ${end.duration / 1000} s played in ` +
      `${wall.toFixed(1)} s wall; at 1000x ${smooth.fps.toFixed(0)} frames/s, ${smooth.ms.toFixed(1)} ms to draw one)`;
    if (problems.length) {
      failed++;
      console.log(`FAIL ${name}\n  ${problems.join("\n  ")}`);
    } else {
      console.log(`ok   ${name}: LEDs drawn ${end.drawn}, screenshot ${shot}`);
    }
    await page.close();
  }
} finally {
  await browser.close();
}
process.exit(failed ? 1 : 0);
