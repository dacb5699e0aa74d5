// The web view end to end in a real browser: a real fleet-server and two fleet-agents over DDS,
// Debian's chromium headless driven by playwright-core. The page loads; clicking an obstacle
// reaches the agents; two clicks on loading areas create an order that ends DONE while the
// robot's drawn position moves; a screenshot is saved with the output. The page is served over
// HTTPS with the web certificate of a security folder made by `fleetctl security init`: the test's
// own requests check it against the folder's authority, the browser trusts that one key alone.
// The viewer's token reads but cannot change anything (403).
//
// node e2e_test.js --bin BUILD/bin --source SOURCE_DIR --out OUTPUT_DIR [--domain N] [--port P]
'use strict';
const crypto = require('crypto');
const fs = require('fs');
const https = require('https');
const path = require('path');
const { spawn } = require('child_process');

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const BIN = args.bin;
const SOURCE = args.source || path.resolve(__dirname, '../..');
const OUT = args.out || path.join(__dirname, 'e2e-output');
const DOMAIN = Number(args.domain || 191);
const PORT = Number(args.port || 18191);
const TOKEN = 'e2e-token-' + process.pid;
const VIEWER_TOKEN = 'e2e-viewer-' + process.pid;
const TIME_SCALE = '10';
const BASE = `https://127.0.0.1:${PORT}`;

if (!BIN) {
  console.error('usage: node e2e_test.js --bin BUILD/bin [--source DIR] [--out DIR]');
  process.exit(2);
}
let launch;
try {
  ({ launch } = require('./browser'));
} catch (e) {
  console.error(`playwright-core is missing in ${__dirname}/node_modules: run scripts/install-deps (npm ci there)\n${e.message}`);
  process.exit(1);
}

fs.rmSync(OUT, { recursive: true, force: true });
fs.mkdirSync(OUT, { recursive: true });

// ---- processes: every child dies with this one (setpriv --pdeathsig), and is stopped at exit ----
const children = [];
function start(name, argv) {
  const log = fs.openSync(path.join(OUT, `${name}.log`), 'w');
  const child = spawn('setpriv', ['--pdeathsig', 'TERM', ...argv], { stdio: ['ignore', log, log] });
  children.push({ name, child });
  return child;
}
function stopAll() {
  for (const { child } of children) if (child.exitCode === null) child.kill('SIGTERM');
}
process.on('exit', stopAll);
for (const sig of ['SIGINT', 'SIGTERM']) process.on(sig, () => { stopAll(); process.exit(1); });
const logOf = (name) => { try { return fs.readFileSync(path.join(OUT, `${name}.log`), 'utf8'); } catch (e) { return ''; } };

const common = ['--config', path.join(SOURCE, 'config/fleet.yaml'), '--domain', String(DOMAIN), '--site', 'table_a',
  '--time-scale', TIME_SCALE];

// ---- checks ----
let failures = 0;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures++;
  return ok;
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
async function until(what, fn, timeoutMs) {
  const end = Date.now() + timeoutMs;
  let value;
  while (Date.now() < end) {
    try { value = await fn(); } catch (e) { value = undefined; }
    if (value) return value;
    await sleep(100);
  }
  throw new Error(`timed out waiting for ${what}`);
}
// ---- HTTPS: the security folder's web certificate, checked against its identity authority ----
const SECURITY = path.join(OUT, 'security');
let authority = '';
function request(method, urlPath, token, body) {
  return new Promise((resolve, reject) => {
    const req = https.request(`${BASE}${urlPath}`, {
      method, ca: authority, headers: { Authorization: `Bearer ${token}`, 'Content-Type': 'application/json' },
    }, (res) => {
      let text = '';
      res.on('data', (d) => { text += d; });
      res.on('end', () => resolve({ status: res.statusCode, text }));
    });
    req.on('error', reject);
    req.end(body);
  });
}
async function state() {
  return JSON.parse((await request('GET', '/api/state', VIEWER_TOKEN)).text);
}
/// base64 SHA-256 of the certificate's public key: what chromium's SPKI allow-list takes.
function spkiHash(pemFile) {
  const key = new crypto.X509Certificate(fs.readFileSync(pemFile)).publicKey;
  return crypto.createHash('sha256').update(key.export({ type: 'spki', format: 'der' })).digest('base64');
}

async function main() {
  const init = start('fleetctl-security-init', [path.join(BIN, 'fleetctl'), '--config', path.join(SOURCE, 'config/fleet.yaml'),
    'security', 'init', SECURITY, '--days', '2']);
  await new Promise((resolve) => init.on('exit', resolve));
  if (!check(init.exitCode === 0, 'fleetctl security init makes a folder with a web certificate')) {
    throw new Error(logOf('fleetctl-security-init'));
  }
  authority = fs.readFileSync(path.join(SECURITY, 'ca/identity_ca.pem'));
  const certificate = path.join(SECURITY, 'web/certificate.pem');
  start('fleet-server', [path.join(BIN, 'fleet-server'), ...common, '--db', path.join(OUT, 'fleet.db'),
    '--http-port', String(PORT), '--api-token', TOKEN, '--viewer-token', VIEWER_TOKEN,
    '--http-tls-cert', certificate, '--http-tls-key', path.join(SECURITY, 'web/key.pem')]);
  start('fleet-agent-fl1', [path.join(BIN, 'fleet-agent'), '--id', 'fl1', ...common]);
  start('fleet-agent-fl2', [path.join(BIN, 'fleet-agent'), '--id', 'fl2', ...common]);
  await until('both robots alive in /api/state', async () => {
    const s = await state();
    return s.robots.filter((r) => r.health === 'alive').length === 2;
  }, 60000);

  // Roles over HTTPS: the viewer reads, and is refused a change.
  const refused = await request('POST', '/api/auto-orders', VIEWER_TOKEN, JSON.stringify({ enabled: false }));
  check(refused.status === 403 && refused.text.includes("the viewer's token does not allow"),
    `the viewer's token cannot POST (${refused.status} ${refused.text})`);
  const stranger = await request('GET', '/api/state', 'guess');
  check(stranger.status === 403, `a wrong token reads nothing (${stranger.status})`);

  const { context, close } = await launch({ trustedKeys: [spkiHash(certificate)] });
  try {
    const page = context.pages()[0] || (await context.newPage());
    const pageErrors = [];
    page.on('pageerror', (e) => pageErrors.push(e.message));
    page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); });
    const external = [];
    page.on('request', (r) => { if (!r.url().startsWith(BASE) && !r.url().startsWith('data:')) external.push(r.url()); });

    // ---- the page loads and draws both robots ----
    await page.goto(`${BASE}/?token=${TOKEN}`);
    await until('both robots drawn', () => page.evaluate(() => window.fleetView && window.fleetView.drawn.fl1 && window.fleetView.drawn.fl2), 20000);
    check((await page.title()).includes('table_a'), 'page title names the site');
    // The list shows the robots that have reported (fl1 and fl2 of the twelve configured), as
    // the stream brings them.
    const rows = await until('robot list rows', async () => {
      const n = await page.locator('#robots tbody tr').count();
      return n >= 2 ? n : 0;
    }, 10000).catch(() => 0);
    check(rows === 2, `robot list has the two robots that run (${rows} rows)`);
    check((await page.locator('#connection').textContent()) === 'live', 'stream is live');

    const canvasBox = await page.locator('#map').boundingBox();
    const clickMap = async (x, y) => {
      const [sx, sy] = await page.evaluate(([mx, my]) => window.fleetView.toScreen(mx, my), [x, y]);
      await page.mouse.click(canvasBox.x + sx, canvasBox.y + sy);
    };
    const site = await page.evaluate(() => window.fleetView.site);

    // ---- two clicks create an order: A1 (a pallet) -> A2 (free) ----
    const s0 = await state();
    check(s0.pallets.A1 === true && s0.pallets.A2 === false, 'A1 holds a pallet and A2 is free at the start');
    const a1 = site.areas.find((a) => a.id === 'A1');
    const a2 = site.areas.find((a) => a.id === 'A2');
    const known = new Set(s0.orders.map((o) => o.id));
    await clickMap(a1.x, a1.y);
    check((await page.locator('#hint').textContent()).includes('A1'), 'the first click selects A1 as the pick area');
    await clickMap(a2.x, a2.y);
    const order = await until('the order in the server state', async () => (await state()).orders.find((o) => !known.has(o.id)), 10000);
    check(order.from === 'A1' && order.to === 'A2', `order ${order.id} goes from A1 to A2`);

    // ---- the robot's drawn position changes between frames while it drives ----
    const robot = await until('a robot assigned', async () => {
      const o = (await state()).orders.find((x) => x.id === order.id);
      return o && o.robot;
    }, 20000);
    // ---- clicking an obstacle reaches the agents over DDS, and the driving robot replans ----
    await until(`${robot} driving`, async () => (await state()).robots.find((r) => r.id === robot).state === 'TRACK_PATH', 20000);
    const o2 = site.obstacles.find((o) => o.id === 'O2');
    const cx = o2.polygon.reduce((a, p) => a + p[0], 0) / o2.polygon.length;
    const cy = o2.polygon.reduce((a, p) => a + p[1], 0) / o2.polygon.length;
    const before = (await state()).obstacles.O2;
    await clickMap(cx, cy);
    await until('O2 switched in the server state', async () => (await state()).obstacles.O2 === !before, 10000);
    check(true, `clicking O2 switched it ${before ? 'off' : 'on'} in the server's state`);
    await until('the page to draw O2 switched', () => page.evaluate((b) => window.fleetView.frame.obstacles.O2 === !b, before), 5000);
    check(true, 'the page shows O2 switched');
    const heard = `static obstacle O2 ${before ? 'disabled' : 'enabled'}`;
    await until('agents to hear of O2', () => logOf('fleet-agent-fl1').includes(heard) && logOf('fleet-agent-fl2').includes(heard), 10000);
    check(true, `both agents logged "${heard}"`);
    const replanned = `replanning order ${order.id} after obstacle O2 was ${before ? 'disabled' : 'enabled'}`;
    await until(`${robot} to replan`, () => logOf(`fleet-agent-${robot}`).includes(replanned), 10000);
    check(true, `${robot} logged "${replanned}"`);
    await page.screenshot({ path: path.join(OUT, 'obstacle.png') });
    // Back off, so that the order drives the usual way.
    await clickMap(cx, cy);
    await until('O2 switched back', async () => (await state()).obstacles.O2 === before, 10000);

    const positions = new Set();
    const samplesEnd = Date.now() + 30000;
    while (Date.now() < samplesEnd && positions.size < 5) {
      const p = await page.evaluate((id) => window.fleetView.drawn[id], robot);
      if (p) positions.add(`${p[0].toFixed(1)},${p[1].toFixed(1)}`);
      await sleep(250);
    }
    check(positions.size >= 5, `${robot}'s drawn position changed between frames (${positions.size} distinct positions)`);
    await page.screenshot({ path: path.join(OUT, 'driving.png') });

    // ---- the order ends DONE, on the page too ----
    const done = await until('the order to end', async () => {
      const o = (await state()).orders.find((x) => x.id === order.id);
      return o && ['DONE', 'FAILED', 'CANCELLED'].includes(o.state) && o;
    }, 150000);
    check(done.state === 'DONE', `order ${order.id} ended ${done.state}${done.reason ? ` (${done.reason})` : ''}`);
    await until('the order table to show DONE', async () =>
      (await page.locator(`#orders tr[data-order="${order.id}"] td:nth-child(5)`).textContent()).startsWith('DONE'), 5000);
    check(true, 'the order table shows DONE');
    await until('the pallet at A2 on the page', () => page.evaluate(() => window.fleetView.frame.pallets.A2 === true), 5000);
    check(true, 'the page shows the pallet at A2');

    // ---- pause and resume from the robot list ----
    const robotState = async (id) => (await state()).robots.find((r) => r.id === id);
    await page.locator('#robots button[data-robot="fl2"][data-action="pause"]').click();
    await until('fl2 PAUSED', async () => (await robotState('fl2')).state === 'PAUSED', 10000);
    check(true, 'the pause button paused fl2');
    await until('the resume button', () => page.locator('#robots button[data-robot="fl2"][data-action="resume"]').count(), 5000);
    await page.locator('#robots button[data-robot="fl2"][data-action="resume"]').click();
    await until('fl2 resumed', async () => (await robotState('fl2')).state !== 'PAUSED', 10000);
    check(true, 'the resume button resumed fl2');

    // ---- switching the map from the page: every robot gets it, the page draws its roads ----
    await page.locator('#map-select').selectOption('table_a_north_closed');
    await page.locator('#map-robot').selectOption('');
    await page.locator('#map-switch').click();
    await until('the server on table_a_north_closed', async () => (await state()).site === 'table_a_north_closed', 10000);
    await until('both robots on the new map', async () =>
      (await state()).robots.every((r) => r.map === 'table_a_north_closed'), 15000);
    check(true, 'the map control switched every robot to table_a_north_closed');
    await until('the page to draw the new roads', () => page.evaluate(() => window.fleetView.site.site === 'table_a_north_closed'), 10000);
    check(true, 'the page redrew the roads of table_a_north_closed');
    await page.screenshot({ path: path.join(OUT, 'map_switched.png') });

    // ---- a lost robot stays on the map, greyed, with its last pose and age ----
    const fl2 = children.find((c) => c.name === 'fleet-agent-fl2').child;
    fl2.kill('SIGKILL');
    await until('fl2 lost on the page', () => page.evaluate(() => window.fleetView.frame.robots.fl2 && window.fleetView.frame.robots.fl2.health === 'lost'), 15000);
    const lastPose = await page.evaluate(() => window.fleetView.drawn.fl2);
    await sleep(1000);
    const stillDrawn = await page.evaluate(() => window.fleetView.drawn.fl2);
    check(!!stillDrawn && stillDrawn[0] === lastPose[0] && stillDrawn[1] === lastPose[1], 'lost fl2 is still drawn at its last pose');
    await until('the robot list to show fl2 lost', async () =>
      (await page.locator('#robots tr.lost[data-robot="fl2"]').count()) === 1, 5000);
    check(true, 'the robot list shows fl2 lost with its age');

    await sleep(500);
    await page.screenshot({ path: path.join(OUT, 'web_view.png') });
    console.log(`screenshots in ${OUT}`);
    check(external.length === 0, `nothing fetched from outside (${external.join(', ') || 'none'})`);
    check(pageErrors.length === 0, `no errors on the page (${pageErrors.join('; ') || 'none'})`);
  } finally {
    await close();
  }
}

main()
  .catch((e) => {
    failures++;
    console.error(`FAIL ${e.message}`);
    for (const { name } of children) console.error(`---- ${name} (last lines)\n${logOf(name).split('\n').slice(-15).join('\n')}`);
  })
  .finally(() => {
    stopAll();
    console.log(failures ? `${failures} check(s) failed` : 'all checks passed');
    process.exit(failures ? 1 : 0);
  });
