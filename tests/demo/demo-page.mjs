// What the demo's browser tests (demo.test.mjs, repair.test.mjs) share: `vite preview` of the
// built demo on a free port, Chromium (Debian `chromium`, driven by playwright-core), pages that
// fail the test on an uncaught error, and the page's load and stats hooks (data-load-count,
// data-state, data-stat).
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { preview } from 'vite';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
/** Screenshots and downloads of the tests (test-artifacts/, made by startSite()). */
export const artifacts = path.join(root, 'test-artifacts');

export async function freePort() {
  return new Promise((resolve, reject) => {
    const srv = net.createServer();
    srv.once('error', reject);
    srv.listen(0, '127.0.0.1', () => {
      const { port } = srv.address();
      srv.close(() => resolve(port));
    });
  });
}

/** `vite preview` of web/demo/dist on a free port of 127.0.0.1: { site, siteUrl }. */
export async function startSite() {
  mkdirSync(artifacts, { recursive: true });
  const site = await preview({
    configFile: path.join(root, 'web/demo/vite.config.js'),
    preview: { port: await freePort(), strictPort: true, host: '127.0.0.1' },
    logLevel: 'warn',
  });
  return { site, siteUrl: site.resolvedUrls.local[0] };
}

/** Headless Chromium (CHROMIUM_PATH, default /usr/bin/chromium). */
export function launchChromium() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM_PATH || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', '--no-first-run'],
  });
}

/** A page 1400 px wide that records its uncaught errors (closePage() asserts there were none). */
export async function newPage(browser, height) {
  const page = await browser.newPage({ viewport: { width: 1400, height } });
  page.errors = [];
  page.on('pageerror', (error) => page.errors.push(error));
  return page;
}

export async function closePage(page) {
  const errors = page.errors.map((e) => e.stack || e.message);
  await page.close();
  assert.deepEqual(errors, [], 'uncaught page errors');
}

/** Waits for the load after `loadCount` to finish (ready or error); returns the state. */
export async function settle(page, loadCount, timeout = 60_000) {
  await page.waitForFunction(
    (n) => Number(document.body.dataset.loadCount) > n && document.body.dataset.state !== 'loading',
    loadCount, { timeout });
  return page.evaluate(() => document.body.dataset.state);
}

/** The statistics the page shows: { key: text } of every [data-stat]. */
export async function pageStats(page) {
  return page.evaluate(() => Object.fromEntries(
    [...document.querySelectorAll('[data-stat]')].map((e) => [e.dataset.stat, e.textContent])));
}
