// node screenshot.js URL OUT.png [seconds]: opens the web view and saves a screenshot after the
// given wall seconds (default 3). For looking at the page and for the README's picture.
'use strict';
const { launch } = require('./browser');

(async () => {
  const [url, out, seconds = '3'] = process.argv.slice(2);
  if (!url || !out) {
    console.error('usage: node screenshot.js URL OUT.png [seconds]');
    process.exit(2);
  }
  const { context, close } = await launch();
  try {
    const page = context.pages()[0] || (await context.newPage());
    page.on('console', (m) => { if (m.type() === 'error') console.error('page:', m.text()); });
    page.on('pageerror', (e) => console.error('page error:', e.message));
    await page.goto(url);
    await page.waitForTimeout(Number(seconds) * 1000);
    await page.screenshot({ path: out });
    console.log(out);
  } finally {
    await close();
  }
})().catch((e) => { console.error(e); process.exit(1); });
