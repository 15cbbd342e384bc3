// What every part of the benchmark shares: the log, the list of errors, medians and rounding,
// and running child processes (plain, or under procstat for wall time and peak RSS).
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { root, opt, BIN } from './bench-options.mjs';

export const log = (...m) => console.error(...m);
export const errors = [];

// ---------------------------------------------------------------------------
// Helpers

export function median(xs) {
  const v = xs.filter((x) => typeof x === 'number' && Number.isFinite(x)).sort((a, b) => a - b);
  if (!v.length) return null;
  const n = v.length;
  return n % 2 ? v[(n - 1) / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}
export const round = (x, d = 3) => (x === null || x === undefined ? null : Number(x.toFixed(d)));

export function run(cmd, args, { timeoutSec = opt.childCap, env } = {}) {
  const r = spawnSync(cmd, args, {
    cwd: root, encoding: 'utf8', maxBuffer: 64 << 20, timeout: timeoutSec * 1000, killSignal: 'SIGKILL',
    env: env ? { ...process.env, ...env } : process.env,
  });
  const timedOut = r.error && r.error.code === 'ETIMEDOUT';
  return { status: r.status, signal: r.signal, stdout: r.stdout || '', stderr: r.stderr || '', timedOut, error: r.error };
}

export function lastJsonLine(text) {
  const lines = text.trim().split('\n').filter((l) => l.startsWith('{'));
  if (!lines.length) throw new Error(`no JSON in output: ${text.slice(0, 300)}`);
  return JSON.parse(lines[lines.length - 1]);
}

// procstat: one whole-process run (wall time + peak RSS), the child's stdout in a temp file.
export const tmpOut = path.join(os.tmpdir(), `stltopo-bench-${process.pid}.out`);
export function procstat(args, timeoutSec = opt.childCap) {
  const r = run(BIN.procstat, ['--stdout', tmpOut, '--timeout', String(timeoutSec), '--', ...args], { timeoutSec: timeoutSec + 30 });
  if (r.status !== 0) throw new Error(`procstat failed: ${r.stderr || r.error}`);
  const p = JSON.parse(r.stdout.trim());
  p.stdout = fs.existsSync(tmpOut) ? fs.readFileSync(tmpOut, 'utf8') : '';
  return p;
}

export function sh(cmd, args) {
  const r = spawnSync(cmd, args, { encoding: 'utf8' });
  return r.status === 0 ? (r.stdout || '').trim() : null;
}
