// Drives the viewer in headless Chromium (Debian's /usr/bin/chromium) with puppeteer-core.
//
//   node browser.mjs test  URL RUN_DIR   the browser test's assertions (crates/view/tests/browser.rs)
//   node browser.mjs missing URL FILE    the page of a run lacking FILE lists it, without error
//   node browser.mjs bench URL [PNG]     time to interactive and to settled, bytes transferred,
//                                        and optionally a screenshot of the settled view
//   node browser.mjs shot URL PNG [IDS]  the settled view without the network's lines nor the
//                                        layers IDS (comma-separated, e.g. water); URL may stand
//                                        inside: #from=x,y,z&to=x,y,z (examples/inside.rs)
//
// puppeteer-core is found through KARSTGEN_NODE_MODULES (set by `cargo xtask test`).
// Prints one JSON line of results; exits 1 with the failed assertions.

import { createRequire } from 'node:module';
import { readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import assert from 'node:assert/strict';

const CHROMIUM = process.env.KARSTGEN_CHROMIUM ?? '/usr/bin/chromium';
const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
  '--disable-component-update', '--disable-sync', '--no-first-run', '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader'];
const VIEWPORT = { width: 1280, height: 800 };

const modules = process.env.KARSTGEN_NODE_MODULES;
if (!modules) {
  console.error('KARSTGEN_NODE_MODULES is not set: run the tests with `cargo xtask test`');
  process.exit(2);
}
const puppeteer = createRequire(path.join(modules, 'noop.js'))('puppeteer-core');

const [mode, url, arg, extra] = process.argv.slice(2);

/** Opens the page, recording console errors, failed requests and the bytes received. */
async function open(browser) {
  const page = await browser.newPage();
  await page.setViewport(VIEWPORT);
  const problems = [];
  const origin = new URL(url).origin;
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => problems.push(`failed: ${r.url()} ${r.failure()?.errorText}`));
  page.on('response', (r) => { if (r.status() >= 400) problems.push(`HTTP ${r.status()}: ${r.url()}`); });
  page.on('request', (r) => {
    if (!r.url().startsWith(origin) && !r.url().startsWith('data:')) problems.push(`outside request: ${r.url()}`);
  });
  const cdp = await page.createCDPSession();
  await cdp.send('Network.enable');
  const traffic = { bytes: 0, requests: 0 };
  cdp.on('Network.loadingFinished', (e) => { traffic.bytes += e.encodedDataLength; traffic.requests += 1; });
  await page.goto(url, { waitUntil: 'load' });
  // Times on the page's clock, from navigation start.
  await page.waitForFunction(() => window.karstView?.ready === true, { timeout: 60_000, polling: 50 });
  const interactive = await page.evaluate(() => window.karstView.readyAt / 1000);
  await page.waitForFunction(() => window.karstView.settled(), { timeout: 120_000, polling: 50 });
  const settled = await page.evaluate(() => performance.now() / 1000);
  return { page, problems, traffic, interactive, settled };
}

/** The share of sample points whose colour differs (by more than 24 in a channel) between a and b. */
function changed(a, b, keep = () => true) {
  let n = 0;
  let total = 0;
  a.forEach((p, i) => {
    if (!keep(i)) return;
    total += 1;
    if (p.some((c, k) => Math.abs(c - b[i][k]) > 24)) n += 1;
  });
  return n / total;
}

const COLUMNS = 160;
const ROWS = 100;
/** Sample points in the middle fifth of the picture, where the camera looks. */
const centre = (i) => Math.abs((i % COLUMNS) - COLUMNS / 2) < COLUMNS / 10 && Math.abs(Math.floor(i / COLUMNS) - ROWS / 2) < ROWS / 10;

const sample = (page) => page.evaluate((c, r) => window.karstView.sample(c, r), COLUMNS, ROWS);
const redraw = (page) => page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));

/** The payload of a JSON artifact: one document {header, payload}. */
function artifact(file) {
  return JSON.parse(readFileSync(file, 'utf8')).payload;
}

async function test(browser, runDir) {
  const { page, problems, traffic } = await open(browser);
  const results = { requests: traffic.requests, bytes: traffic.bytes };

  // Not blank: many colours, and most points not the background.
  const before = await sample(page);
  const background = before[0];
  const distinct = new Set(before.map((p) => p.join(','))).size;
  const notBackground = before.filter((p) => p.some((c, k) => Math.abs(c - background[k]) > 24)).length / before.length;
  assert.ok(distinct > 50, `the picture has only ${distinct} colours`);
  assert.ok(notBackground > 0.1, `only ${notBackground} of the picture is not background`);

  // The cave layer: toggling it changes the picture, where the camera looks above all.
  await page.click('#layer-cave');
  await redraw(page);
  const noCave = await sample(page);
  results.caveChange = changed(before, noCave);
  results.caveChangeCentre = changed(before, noCave, centre);
  assert.ok(results.caveChange > 0.005, `hiding the cave changed ${results.caveChange} of the picture`);
  // The centre (where the camera looks) changes several times more than the picture as a whole;
  // its share depends on the cave mesh's cell (4.8 % on the default scene at a 1.87 m cave cell).
  assert.ok(results.caveChangeCentre > 0.03, `hiding the cave changed ${results.caveChangeCentre} of the centre`);
  await page.click('#layer-cave');
  await redraw(page);

  // The surface streams: lines in their Table 1 colours, their legend listing the types of
  // streams.json; hiding the layer removes both. With every other layer hidden, each segment's
  // midpoint (or a pixel next to it: lines are one antialiased pixel wide) is the background
  // tinted towards its type's colour, and the background alone without the layer.
  const streams = artifact(path.join(runDir, 'streams.json'));
  const types = [...new Set(streams.segments.map((s) => s.water))].sort();
  const streamLegend = () => page.$$eval('#stream-legend .row', (els) => els.filter((e) => e.offsetParent).map((e) => e.textContent.trim()));
  assert.deepEqual((await streamLegend()).sort(), types, 'the streams legend lists the types of streams.json');
  const inView = (p) => p && p.x > 2 && p.y > 2 && p.x < VIEWPORT.width - 360 && p.y < VIEWPORT.height - 2;
  const marks = (await page.evaluate(() => window.karstView.streams())).filter((m) => inView(m.at));
  assert.equal(marks.length, streams.segments.length, 'every surface segment is on screen');
  const others = ['terrain', 'cave', 'water', 'network', 'keypoints', 'water-tables', 'horizons'];
  const toggle = async (ids) => {
    for (const id of ids) await page.click(`#layer-${id}`);
    await redraw(page);
  };
  const around = marks.flatMap((m) => [-1, 0, 1].flatMap((dy) => [-1, 0, 1].map((dx) => ({ x: m.at.x + dx, y: m.at.y + dy }))));
  const pixels = async () => {
    const all = await page.evaluate((points) => window.karstView.pixelsAt(points), around);
    return marks.map((m, i) => all.slice(9 * i, 9 * i + 9));
  };
  await toggle(others);
  const lit = await pixels();
  await toggle(['streams']);
  const hidden = await pixels();
  assert.deepEqual(await streamLegend(), [], 'the streams legend hides with its layer');
  await toggle(['streams', ...others]);
  const clear = hidden[0][0];
  // How far each pixel goes from the clear towards the colour (1: the colour), and how
  // well its change points that way (cosine).
  const tint = (p, colour) => {
    const [d, c] = [p.map((v, k) => v - clear[k]), colour.map((v, k) => v - clear[k])];
    const dot = d.reduce((a, v, k) => a + v * c[k], 0);
    return { amount: dot / c.reduce((a, v) => a + v * v, 0), cosine: dot / (Math.hypot(...d) * Math.hypot(...c) || 1) };
  };
  const drawn = marks.filter((m, i) => lit[i].some((p) => {
    const t = tint(p, m.colour);
    return t.amount > 0.3 && t.cosine > 0.95;
  })).length;
  const ghosts = hidden.flat().filter((p) => p.some((v, k) => Math.abs(v - clear[k]) > 8)).length;
  results.streams = { segments: marks.length, drawn, types };
  assert.ok(drawn === marks.length, `only ${drawn} of ${marks.length} surface segments show their type's colour`);
  assert.equal(ghosts, 0, 'nothing is left where the streams were once their layer is hidden');

  // Picking: click the middle of the segment drawn farthest from every other segment and from
  // the nodes a click picks first (conduit ends: junctions, dead ends; key points).
  const data = await page.evaluate(() => ({
    conduits: window.karstView.data.skeleton.conduits.map((c) => ({ nodes: c.nodes, types: c.types })),
    keypoints: window.karstView.data.skeleton.nodes.flatMap((n, i) => (n.keypoint ? [i] : [])),
  }));
  const screen = await page.evaluate(() => window.karstView.projectNodes());
  const segments = data.conduits.flatMap((c, ci) => c.nodes.slice(1).map((b, i) => ({ ci, i, a: c.nodes[i], b })));
  const pickedFirst = [...new Set([...data.conduits.flatMap((c) => [c.nodes[0], c.nodes[c.nodes.length - 1]]), ...data.keypoints])];
  const onScreen = (p) => p && p.x > 20 && p.y > 20 && p.x < VIEWPORT.width - 360 && p.y < VIEWPORT.height - 20;
  const toSegment = (x, y, p, q) => {
    const [dx, dy] = [q.x - p.x, q.y - p.y];
    const l2 = dx * dx + dy * dy || 1;
    const t = Math.min(Math.max(((x - p.x) * dx + (y - p.y) * dy) / l2, 0), 1);
    return Math.hypot(x - p.x - t * dx, y - p.y - t * dy);
  };
  let target = null;
  for (const s of segments) {
    const [p, q] = [screen[s.a], screen[s.b]];
    if (!onScreen(p) || !onScreen(q) || Math.hypot(q.x - p.x, q.y - p.y) < 8) continue;
    const [x, y] = [(p.x + q.x) / 2, (p.y + q.y) / 2];
    const fromSegments = Math.min(...segments.filter((o) => o !== s && screen[o.a] && screen[o.b])
      .map((o) => toSegment(x, y, screen[o.a], screen[o.b])));
    // A node within the viewer's 6 px node tolerance would be picked instead.
    const fromNodes = Math.min(...pickedFirst.filter((n) => screen[n]).map((n) => Math.hypot(screen[n].x - x, screen[n].y - y))) - 6;
    const clearance = Math.min(fromSegments, fromNodes);
    if (!target || clearance > target.clearance) target = { ...s, x, y, clearance };
  }
  assert.ok(target && target.clearance > 3, `no conduit segment stands alone on screen (best: ${JSON.stringify(target)})`);
  await page.mouse.click(target.x, target.y);
  await redraw(page);
  const info = await page.$eval('#info', (e) => e.innerText);
  results.picked = { conduit: target.ci, segment: target.i };
  assert.match(info, new RegExp(`Conduit ${target.ci}, segment ${target.i + 1} of`), info);
  assert.match(info, new RegExp(`type\\s+${data.conduits[target.ci].types[target.i]}`), info);
  assert.match(info, /route\s+to /, info);

  // The metrics panel shows metrics.json's values.
  const metrics = artifact(path.join(runDir, 'metrics.json'));
  const shown = await page.$$eval('[data-metric]', (els) => Object.fromEntries(els.map((e) => [e.dataset.metric, e.querySelector('.value').textContent])));
  for (const [key, compared] of Object.entries(metrics.karstnet)) {
    const expected = compared.value === null ? 'undefined' : compared.value.toFixed(3);
    assert.equal(shown[key], expected, `metric ${key}`);
  }
  assert.equal(Object.keys(shown).length, Object.keys(metrics.karstnet).length);
  const nodes = await page.$eval('[data-count="n_nodes_full"]', (e) => e.textContent);
  assert.equal(nodes, `${metrics.network.n_nodes_full}`);

  // The section slider: keeping only the lower half changes what is visible.
  const full = await sample(page);
  await page.$eval('#section', (input) => {
    input.value = (Number(input.min) + Number(input.max)) / 2;
    input.dispatchEvent(new Event('input'));
  });
  await redraw(page);
  const cut = await sample(page);
  results.sectionChange = changed(full, cut);
  assert.ok(results.sectionChange > 0.01, `the section changed ${results.sectionChange} of the picture`);

  // The walk moves the camera; the screenshot button makes a PNG.
  const home = await page.evaluate(() => window.karstView.cameraPosition());
  await page.click('#walk');
  await new Promise((resolve) => { setTimeout(resolve, 600); });
  const walking = await page.evaluate(() => [window.karstView.walking(), window.karstView.cameraPosition()]);
  assert.ok(walking[0], 'the walk started');
  assert.ok(Math.hypot(...walking[1].map((v, k) => v - home[k])) > 1, 'the walk moved the camera');
  await page.click('#walk');
  await page.click('#screenshot');
  const png = await page.evaluate(() => window.karstView.lastScreenshot ?? '');
  assert.ok(png.startsWith('data:image/png;base64,') && png.length > 10_000, 'the screenshot is a PNG');

  assert.deepEqual(problems, [], 'no console error, failed request or outside request');
  return results;
}

async function missing(browser, file) {
  const { page, problems } = await open(browser);
  const listed = await page.$eval('#problems', (e) => (e.hidden ? '' : e.innerText));
  assert.match(listed, new RegExp(`${file.replace('.', '\\.')}`), `the page lists ${file}: "${listed}"`);
  const disabled = await page.$$eval('#layers input:disabled', (els) => els.map((e) => e.id));
  assert.ok(['layer-cave', 'layer-terrain', 'layer-streams'].every((l) => disabled.includes(l)), `disabled layers: ${disabled}`);
  const picture = await sample(page);
  assert.ok(new Set(picture.map((p) => p.join(','))).size > 20, 'the network and key points are still drawn');
  assert.deepEqual(problems, [], 'no console error, failed request or outside request');
  return { listed: listed.split('\n').length - 1, disabled };
}

async function bench(browser, png) {
  const { page, problems, traffic, interactive, settled } = await open(browser);
  const triangles = await page.evaluate(() => window.karstView.triangles());
  const marks = await page.evaluate(() => Object.fromEntries(performance.getEntriesByType('mark')
    .map((m) => [m.name.replace('karst:', ''), Math.round(m.startTime) / 1000])));
  if (png) {
    await page.evaluate(() => { document.getElementById('status').textContent = ''; });
    await page.screenshot({ path: png });
  }
  assert.deepEqual(problems, []);
  return { interactive, settled, marks, megabytes: traffic.bytes / 1e6, requests: traffic.requests, triangles };
}

async function shot(browser, png, hidden = '') {
  const { page, problems } = await open(browser);
  for (const id of ['network', ...hidden.split(',').filter(Boolean)]) {
    const layer = await page.$(`#layer-${id}`);
    if (layer && await layer.evaluate((e) => e.checked && !e.disabled)) await layer.click();
  }
  await page.waitForFunction(() => window.karstView.settled(), { timeout: 120_000, polling: 50 });
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  const canvas = await page.$('#canvas');
  await canvas.screenshot({ path: png });
  assert.deepEqual(problems, []);
  return { png, camera: await page.evaluate(() => window.karstView.cameraPosition()) };
}

const browser = await puppeteer.launch({ executablePath: CHROMIUM, args: FLAGS, headless: true });
try {
  const run = { test, missing, bench, shot }[mode];
  if (!run) throw new Error(`unknown mode ${mode}: test, missing, bench or shot`);
  const results = await run(browser, arg, extra);
  console.log(JSON.stringify(results));
} catch (e) {
  console.error(e.message);
  process.exitCode = 1;
} finally {
  await browser.close();
}
