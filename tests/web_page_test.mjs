// The service's page in a real browser (issue 19): Debian's chromium, driven by playwright-core.
// Starts `tpmsfill serve` on a free port, opens the page with the token in the address, tries a
// wrong token, drops the femur on the page, reads the check verdict and the preview, fills it,
// follows the progress, sees the result drawn in the 3D view, downloads it, and checks the
// download with `tpmsfill check` as a closed, outward 2-manifold of the triangles shown.
//
// Environment (tests/CMakeLists.txt sets it): TPMSFILL_CLI, TPMSFILL_NODE_MODULES, FEMUR,
// SCRATCH; CHROMIUM (default /usr/bin/chromium); SCREENSHOT (optional: a PNG of the page).
// Exit 77 (ctest: skipped, with the sentence) when chromium or playwright-core is missing.
import assert from 'node:assert/strict';
import { execFileSync, spawn } from 'node:child_process';
import { randomBytes } from 'node:crypto';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';

const env = (name) => {
  if (!process.env[name]) throw new Error(`set ${name}`);
  return process.env[name];
};
const chromiumPath = process.env.CHROMIUM || '/usr/bin/chromium';
if (!fs.existsSync(chromiumPath)) {
  console.log(`skipped: no chromium at ${chromiumPath} (Debian: apt-get install chromium; scripts/test.sh tries)`);
  process.exit(77);
}
let chromium;
try {
  ({ chromium } = createRequire(path.join(env('TPMSFILL_NODE_MODULES'), 'x'))('playwright-core'));
} catch {
  console.log('skipped: playwright-core is not in the build (npm ci in the build folder brings it)');
  process.exit(77);
}
const femur = env('FEMUR');
if (!fs.existsSync(femur)) {
  console.log('skipped: femur.off is missing (Debian: libcgal-demo)');
  process.exit(77);
}

const scratch = env('SCRATCH');
fs.rmSync(scratch, { recursive: true, force: true });
fs.mkdirSync(scratch, { recursive: true });
const token = randomBytes(24).toString('hex');
fs.writeFileSync(path.join(scratch, 'token'), token, { mode: 0o600 });

// The server, on a port the system picks; its first line says which.
const server = spawn(env('TPMSFILL_CLI'), ['serve', '--listen', '127.0.0.1:0', '--data',
  path.join(scratch, 'data'), '--token-file', path.join(scratch, 'token')], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  let text = '';
  server.stdout.on('data', (chunk) => {
    text += chunk;
    const match = /listening on (http:\/\/\S+)/.exec(text);
    if (match) resolve(match[1]);
  });
  server.on('exit', (code) => reject(new Error(`the server stopped (exit ${code}) before listening`)));
  setTimeout(() => reject(new Error('the server did not listen within 20 s')), 20000);
});

const browser = await chromium.launch({
  executablePath: chromiumPath,
  // Offline and headless: no sandbox as root, WebGL through SwiftShader (no GPU), and none of
  // the background connections a closed network refuses.
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync'],
});
let failed = false;
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 }, acceptDownloads: true });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.on('console', (m) => m.type() === 'error' && pageErrors.push(m.text()));

  // Drops a file on the drop zone as a person would (a DataTransfer with the file in it).
  const dropFile = async (name, bytes) => {
    await page.evaluate(([n, b64]) => {
      const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
      const transfer = new DataTransfer();
      transfer.items.add(new File([bytes], n));
      document.getElementById('drop').dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, bubbles: true, cancelable: true }));
    }, [name, bytes.toString('base64')]);
  };

  const t0 = performance.now();
  await page.goto(`${url}/#token=${token}`, { waitUntil: 'load' });
  const loaded = performance.now() - t0;
  assert.equal(await page.inputValue('#token'), token, 'the token from the address fills the field');
  // Every control has a label a screen reader reads, and the live regions are announced.
  const unlabelled = await page.evaluate(() =>
    [...document.querySelectorAll('input, select, button')]
      .filter((e) => !(e.labels?.length || e.textContent.trim()))
      .map((e) => e.id || e.outerHTML));
  assert.deepEqual(unlabelled, [], 'every control has a label');
  for (const id of ['verdict', 'stage', 'outcome'])
    assert.equal(await page.getAttribute(`#${id}`, 'aria-live'), 'polite', `#${id} is a live region`);
  assert.ok(!page.url().includes(token), 'the token is dropped from the address bar');

  // A wrong token: the service's sentence, and nothing to fill.
  await page.fill('#token', 'not-the-token-at-all');
  await dropFile('femur.off', fs.readFileSync(femur));
  await page.waitForSelector('#verdict .bad', { timeout: 20000 });
  assert.match(await page.textContent('#verdict'), /send the service's token/);
  assert.ok(await page.isDisabled('#start'), 'Fill stays disabled without a verdict');
  await page.fill('#token', token);
  pageErrors.length = 0;  // the browser logs the 401 above

  // The femur (1 unit long): its verdict and preview.
  await page.selectOption('#units', 'mm');
  await page.fill('#scale', '35');
  const t1 = performance.now();
  await dropFile('femur.off', fs.readFileSync(femur));
  await page.waitForSelector('#verdict .ok', { timeout: 30000 });
  const verdictTime = performance.now() - t1;
  const verdict = await page.textContent('#verdict');
  assert.match(verdict, /ready to fill/);
  assert.match(verdict, /7,798/, 'the check counts the femur\'s 7798 triangles');
  assert.match(verdict, /35 mm/, 'the size is shown in mm after the scale');
  await page.selectOption('#units', 'cm');  // modelled in cm: ten times longer
  assert.match(await page.textContent('#verdict'), /350 mm/, 'the size follows the units chosen');
  await page.selectOption('#units', 'mm');
  assert.equal(await page.getAttribute('#viewer', 'data-shown'), 'input');
  assert.equal(await page.getAttribute('#viewer', 'data-triangles'), '7798');

  // The design: the demo's gyroid, porosity 0.7. Every progress line the page shows is kept.
  await page.selectOption('#type', 'gyroid');
  await page.fill('#cell', '2');
  await page.fill('#porosity', '0.7');
  await page.fill('#voxel', '0.1');
  await page.evaluate(() => {
    window.stagesSeen = [];
    new MutationObserver(() => window.stagesSeen.push(document.getElementById('stage').textContent))
      .observe(document.getElementById('stage'), { childList: true, characterData: true, subtree: true });
  });
  const t2 = performance.now();
  await page.click('#start');
  await page.waitForSelector('#download:not([hidden])', { timeout: 120000 });
  const fetchedTime = performance.now() - t2;
  await page.waitForFunction(() => document.getElementById('viewer').dataset.shown === 'result', null, { timeout: 60000 });
  const fillTime = performance.now() - t2;
  const stages = await page.evaluate(() => window.stagesSeen);
  assert.ok(stages.some((s) => /\[\d+\/\d+\]/.test(s)), `the page showed the job's stages (saw: ${stages.join(' | ')})`);
  const outcome = await page.textContent('#outcome');
  assert.match(outcome, /Written and checked/);
  const porosity = Number(/Porosity\s*([\d.]+) %/.exec(outcome)[1]);
  assert.ok(Math.abs(porosity - 70) < 2, `porosity ${porosity} % is the 70 % asked, within 2 points`);
  const shown = Number(await page.getAttribute('#viewer', 'data-triangles'));
  assert.ok(shown > 10000, `the result has ${shown} triangles`);

  // The 3D view drew it: a good share of the canvas is not the background.
  const webgl = await page.evaluate(() => !!document.querySelector('#viewer canvas'));
  assert.ok(webgl, 'the 3D view has a WebGL canvas');
  const coverage = await page.evaluate(() => {
    const source = document.querySelector('#viewer canvas');
    const canvas = Object.assign(document.createElement('canvas'), { width: source.width, height: source.height });
    const context = canvas.getContext('2d');
    context.drawImage(source, 0, 0);
    const { data } = context.getImageData(0, 0, canvas.width, canvas.height);
    const [r0, g0, b0, a0] = data;  // a corner: the background
    let drawn = 0;
    for (let i = 0; i < data.length; i += 4)
      if (Math.abs(data[i] - r0) + Math.abs(data[i + 1] - g0) + Math.abs(data[i + 2] - b0) + Math.abs(data[i + 3] - a0) > 24) ++drawn;
    return drawn / (data.length / 4);
  });
  assert.ok(coverage > 0.05, `the lattice covers ${(100 * coverage).toFixed(1)} % of the view`);
  if (process.env.SCREENSHOT) await page.screenshot({ path: process.env.SCREENSHOT, fullPage: true });

  // The download is the lattice shown, and a valid solid.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download')]);
  const file = path.join(scratch, download.suggestedFilename());
  await download.saveAs(file);
  assert.match(path.basename(file), /^femur-gyroid\.stl$/);
  const bytes = fs.readFileSync(file);
  assert.equal(bytes.readUInt32LE(80), shown, 'the binary STL holds the triangles shown');
  assert.equal(bytes.length, 84 + 50 * shown);
  const check = JSON.parse(execFileSync(env('TPMSFILL_CLI'), ['check', file, '--json']).toString());
  assert.ok(check.closed && check.manifold && check.outward && check.consistently_oriented, 'the download is a closed, outward 2-manifold');
  assert.equal(check.self_intersecting_pairs, 0);

  // A sheet set by its wall thickness: the field appears for sheets only. Walls of 0.25 mm
  // at a voxel of 0.15 mm are thinner than two voxels: fill warns, and the page lists the
  // warning as a sentence.
  assert.ok(await page.isHidden('#thickness'), 'no wall thickness for a network');
  await page.selectOption('#style', 'sheet');
  assert.ok(await page.isVisible('#thickness'));
  await page.fill('#cell', '3');
  await page.fill('#thickness', '0.25');
  await page.fill('#voxel', '0.15');
  await page.click('#start');
  await page.waitForFunction((before) => /Written and checked/.test(document.getElementById('outcome').textContent) &&
    document.getElementById('viewer').dataset.triangles !== before, String(shown), { timeout: 120000 });
  const sheet = await page.evaluate(() => document.getElementById('outcome').textContent);
  assert.ok(Number(await page.getAttribute('#viewer', 'data-triangles')) > 10000, 'the sheet is drawn');
  assert.doesNotMatch(sheet, /asked/, 'a thickness, not a porosity, was asked for');
  const warnings = await page.$$eval('#outcome li.warn', (items) => items.map((li) => li.textContent));
  assert.ok(warnings.some((w) => /thinner than two voxels/.test(w)), `the warning is listed (saw: ${warnings.join(' | ')})`);
  assert.ok(warnings.every((w) => w.length > 20), 'each item is a whole sentence');

  // A design that cannot come out as asked: the command's sentence, nothing drawn anew.
  await page.selectOption('#style', 'network');
  await page.fill('#cell', '2');
  await page.fill('#voxel', '1.5');
  await page.click('#start');
  await page.waitForSelector('#outcome .bad', { timeout: 60000 });
  assert.match(await page.textContent('#outcome'), /voxel/, 'the refusal names the voxel');
  assert.ok(await page.isHidden('#download'), 'no download for a refused job');

  // Cancel: a long fill (voxel 0.04 mm: 16 times the nodes, seconds) stopped from the page.
  await page.fill('#voxel', '0.04');
  await page.click('#start');
  await page.waitForFunction(() => /\[\d+\/\d+\]/.test(document.getElementById('stage').textContent), null, { timeout: 60000 });
  await page.click('#cancel');
  await page.waitForFunction(() => /Cancelled/.test(document.getElementById('outcome').textContent), null, { timeout: 60000 });
  assert.ok(await page.isHidden('#download'), 'nothing to download after a cancel');
  assert.ok(await page.isEnabled('#start'), 'Fill can be pressed again');
  assert.ok(await page.isHidden('#cancel') && await page.isHidden('#progress-box'), 'no Cancel or progress when idle');

  assert.deepEqual(pageErrors, [], 'no errors in the page');
  const marks = await page.evaluate(() => {
    const at = Object.fromEntries(performance.getEntriesByType('mark').map((m) => [m.name, m.startTime]));
    const step = (a, b) => (at[b] - at[a]).toFixed(0);
    return `job ${step('fill-sent', 'fill-ended')} ms, download ${step('fill-ended', 'result-fetched')} ms, ` +
      `STL read ${step('result-fetched', 'result-read')} ms, drawn ${step('result-read', 'result-drawn')} ms`;
  });
  console.log(`fill in the page: ${marks}`);
  console.log(`timings: page loaded in ${loaded.toFixed(0)} ms; femur dropped to verdict in ${verdictTime.toFixed(0)} ms; Fill pressed to the result downloaded in ${fetchedTime.toFixed(0)} ms and drawn in ${fillTime.toFixed(0)} ms`);
  console.log(`passed: femur checked, filled (${shown} triangles, porosity ${porosity} %), drawn over ${(100 * coverage).toFixed(1)} % of the view, downloaded and valid`);
} catch (e) {
  failed = true;
  console.error(e.stack ?? e.message);
  if (process.env.SCREENSHOT) await browser.contexts()[0]?.pages()[0]?.screenshot({ path: process.env.SCREENSHOT }).catch(() => {});
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
process.exit(failed ? 1 : 0);
