// The page's drawing speed with many robots (target: >= 30 frames per second in headless
// chromium with 50 robots). Starts `web_bench --serve` (synthetic robots streamed at 20 Hz),
// opens the page with ?fps (it then redraws on every animation frame, news or not) and counts
// frames drawn over a window. Reports; asserts nothing.
//
// node fps_bench.js --bin BUILD/bin [--robots 50] [--seconds 10] [--port 18098]
'use strict';
const path = require('path');
const { spawn } = require('child_process');
const { launch } = require('./browser');

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const robots = Number(args.robots || 50);
const seconds = Number(args.seconds || 10);
const port = Number(args.port || 18098);
if (!args.bin) {
  console.error('usage: node fps_bench.js --bin BUILD/bin [--robots 50] [--seconds 10]');
  process.exit(2);
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

(async () => {
  const server = spawn('setpriv', ['--pdeathsig', 'TERM', path.join(args.bin, 'web_bench'), '--serve', '--robots',
    String(robots), '--port', String(port), '--seconds', String(seconds + 30)], { stdio: ['ignore', 'ignore', 'inherit'] });
  const { context, close } = await launch();
  try {
    const page = context.pages()[0] || (await context.newPage());
    for (let i = 0; i < 50; i++) {
      try { await page.goto(`http://127.0.0.1:${port}/?fps&token=bench`); break; } catch (e) { await sleep(200); }
    }
    // Polled with evaluate(): waitForFunction evaluates strings, which the page's CSP forbids.
    const end = Date.now() + 20000;
    while (!(await page.evaluate((n) => !!window.fleetView && Object.keys(window.fleetView.drawn).length >= n, robots))) {
      if (Date.now() > end) throw new Error('the robots were not drawn within 20 s');
      await sleep(100);
    }
    await sleep(2000);  // warm-up
    const a = await page.evaluate(() => ({ t: performance.now(), ...window.fleetView.stats }));
    await sleep(seconds * 1000);
    const b = await page.evaluate(() => ({ t: performance.now(), ...window.fleetView.stats }));
    const dt = (b.t - a.t) / 1000;
    await page.screenshot({ path: path.join(args.out || '.', `fps_${robots}_robots.png`) });
    console.log(JSON.stringify({
      robots,
      seconds: Math.round(dt * 10) / 10,
      frames_drawn_per_s: Math.round(((b.draws - a.draws) / dt) * 10) / 10,
      animation_frames_per_s: Math.round(((b.rafs - a.rafs) / dt) * 10) / 10,
      stream_events_per_s: Math.round(((b.events - a.events) / dt) * 10) / 10,
    }));
  } finally {
    await close();
    server.kill('SIGTERM');
  }
})().catch((e) => { console.error(e); process.exit(1); });
