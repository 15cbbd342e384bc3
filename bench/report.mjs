// The report: the environment of a run, the medians, per-triangle figures, cross-checks and
// ratios of each case, the targets of issue 7, the markdown tables and the JSON results.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { root, rel, SIZES, HALFEDGE_SIZES, opt, BIN } from './bench-options.mjs';
import { errors, median, round, sh } from './bench-util.mjs';


// ---------------------------------------------------------------------------
// Environment

function gitInfo() {
  const commit = sh('git', ['-C', root, 'rev-parse', 'HEAD']);
  const dirty = sh('git', ['-C', root, 'status', '--porcelain', '--', 'src', 'bindings', 'web/src', 'CMakeLists.txt']);
  return { commit, dirtySources: dirty === null ? null : dirty.length > 0 };
}
function pkgVersion(name) {
  try { return JSON.parse(fs.readFileSync(path.join(root, 'node_modules', name, 'package.json'), 'utf8')).version; } catch { return null; }
}
const cpuModel = (os.cpus()[0] || {}).model || 'unknown';
export function collectEnvironment() {
  return {
    date: new Date().toISOString(),
    machine: {
      cpu: cpuModel, cores: os.cpus().length, memoryGiB: round(os.totalmem() / 2 ** 30, 1),
      os: `${os.type()} ${os.release()}`, distro: (() => { try { return (fs.readFileSync('/etc/os-release', 'utf8').match(/PRETTY_NAME="([^"]+)"/) || [])[1] || null; } catch { return null; } })(),
      loadAverageAtStart: os.loadavg().map((x) => round(x, 2)),
    },
    versions: {
      node: process.version,
      cxx: (() => { const v = (sh('c++', ['--version']) || '').split('\n')[0]; const m = v.match(/^(\S+).*?(\d+\.\d+\.\d+)/); return m ? `${m[1] === 'c++' ? 'g++' : m[1]} ${m[2]}` : v || null; })(),
      emcc: (() => { const m = (sh('emcc', ['--version']) || '').match(/(\d+\.\d+\.\d+)/); return m ? `emcc ${m[1]}` : null; })(),
      admesh: ((sh(BIN.admesh, ['--version']) || '').match(/[\d.]+/) || [null])[0],
      three: pkgVersion('three'),
      'three-mesh-halfedge': pkgVersion('three-mesh-halfedge'),
      stltopo: JSON.parse(fs.readFileSync(path.join(root, 'package.json'), 'utf8')).version,
    },
    git: gitInfo(),
    wasmBuiltAt: fs.statSync(path.join(root, 'dist/stltopo-wasm.wasm')).mtime.toISOString(),
    options: { sizes: opt.sizes, reps: opt.reps, warm: opt.warm, quick: opt.quick, tiny: opt.tiny, halfedgeCapSec: opt.halfedgeCap, only: opt.only ? String(opt.only) : null, contenders: opt.contenders },
  };
}

// ---------------------------------------------------------------------------
// Medians, per-triangle figures and ratios

export function summarize(c, samples, idle) {
  const bytes = fs.statSync(c.file).size;
  const out = { id: c.id, size: c.size, format: c.format, order: c.order, holes: c.holes, file: rel(c.file), bytes, triangles: null, contenders: {}, checks: {}, ratios: {} };
  const tri = () => out.triangles;
  const perTri = (bytesAbove) => (bytesAbove === null || !tri() ? null : round(bytesAbove / tri(), 1));
  const mps = (ms) => (ms && tri() ? round(tri() / ms / 1000, 3) : null); // million triangles / s
  const ok = (k) => (samples[k] || []).filter((s) => !s.timedOut);
  const med = (xs, f) => median(xs.map(f));

  if (ok('native').length) {
    const s = ok('native');
    out.triangles = s[0].triangles;
    const stages = (key) => {
      const xs = s.map((x) => x[key]).filter(Boolean);
      if (!xs.length) return null;
      return { readMs: round(med(xs, (x) => x.readMs)), topologyMs: round(med(xs, (x) => x.topologyMs)), reportMs: round(med(xs, (x) => x.reportMs)), totalMs: round(med(xs, (x) => x.totalMs)), cpuMs: round(med(xs, (x) => x.cpuMs)) };
    };
    const first = stages('first');
    const warm = stages('warm') || first;
    out.contenders.native = { reps: s.length, first, warm, timeMs: warm.totalMs, mTrianglesPerSecond: mps(warm.totalMs), vertices: s[0].vertices, holes: s[0].holes, boundaryEdges: s[0].boundaryEdges, edges: s[0].edges, shells: s[0].shells };
    const st = s.map((x) => x.streamed).filter(Boolean);
    if (st.length) out.contenders.native.fullTopologyStreamedBytesPerTriangle = perTri(med(st, (x) => (x.peakRssKiB - x.rssBeforeKiB) * 1024));
  }
  for (const k of ['native-cli', 'admesh']) {
    const s = ok(k);
    if (!s.length) continue;
    if (out.triangles === null) out.triangles = s[0].triangles;
    const wall = round(med(s, (x) => x.wallMs));
    const rss = med(s, (x) => x.maxRssKiB);
    const idleKiB = k === 'admesh' ? idle.admeshKiB : idle.cliKiB;
    out.contenders[k] = {
      reps: s.length, timeMs: wall, wallMs: wall, cpuMs: round(med(s, (x) => x.cpuMs)), mTrianglesPerSecond: mps(wall),
      peakRssKiB: rss, idleRssKiB: idleKiB, bytesPerTriangle: perTri((rss - idleKiB) * 1024),
    };
    if (k === 'native-cli') {
      const one = s.filter((x) => x.allThreads);
      Object.assign(out.contenders[k], { vertices: s[0].vertices, holes: s[0].holes, boundaryEdges: s[0].boundaryEdges,
        allThreadsWallMs: one.length ? round(med(one, (x) => x.allThreads.wallMs)) : null,
        allThreadsCpuMs: one.length ? round(med(one, (x) => x.allThreads.cpuMs)) : null });
    }
    else Object.assign(out.contenders[k], { disconnectedEdges: s[0].disconnectedEdges });
  }
  for (const k of ['wasm-read', 'wasm-full', 'wasm-view', 'wasm-full-kept', 'three', 'three-kept', 'three-halfedge']) {
    const all = samples[k] || [];
    if (!all.length) continue;
    const s = ok(k);
    if (!s.length) {
      out.contenders[k] = { reps: 0, timedOut: true, capMs: all[0].capMs, timeMs: null, lowerBoundMs: all[0].capMs };
      continue;
    }
    if (out.triangles === null) out.triangles = s[0].triangles;
    const first = round(med(s, (x) => x.firstMs));
    const warmPer = s.map((x) => median(x.warmMs));
    const warm = round(median(warmPer));
    const r = {
      reps: s.length, initMs: round(med(s, (x) => x.initMs)), firstMs: first, warmMs: warm, timeMs: warm ?? first,
      firstCpuMs: round(med(s, (x) => x.firstCpuMs)), warmCpuMs: round(median(s.map((x) => median(x.warmCpuMs || [])))),
      mTrianglesPerSecond: mps(warm ?? first),
      rssAboveIdleKiB: med(s, (x) => x.rssPeakKiB - x.rssIdleKiB),
      rssBytesPerTriangle: perTri(med(s, (x) => (x.rssPeakKiB - x.rssIdleKiB) * 1024)),
      vertices: s[0].vertices,
    };
    if (all.some((x) => x.timedOut)) r.someTimedOut = true;
    if (k.startsWith('wasm')) {
      r.heapBytes = Math.max(...s.map((x) => x.heapBytes));
      r.heapIdleBytes = s[0].heapIdleBytes;
      r.heapBytesPerTriangle = perTri(r.heapBytes);
      r.holes = s[0].holes;
      if (k === 'wasm-full' || k === 'wasm-full-kept') r.derivedHalfedgesMs = round(med(s, (x) => x.derivedHalfedgesMs));
    } else {
      const st = (pick) => {
        const xs = s.map(pick).filter(Boolean);
        if (!xs.length) return null;
        const o = {};
        for (const key of Object.keys(xs[0])) o[key] = round(med(xs, (x) => x[key]));
        return o;
      };
      r.firstStages = st((x) => x.firstStages);
      r.warmStages = st((x) => (x.warmStages && x.warmStages.length ? x.warmStages[x.warmStages.length - 1] : null));
      if (k === 'three-halfedge') {
        r.halfedges = s[0].halfedges;
        r.boundaryHalfedges = s[0].boundaryHalfedges;
      }
    }
    out.contenders[k] = r;
  }
  out.samples = samples; // every measurement, as the children reported it
  out.mbytesPerSecondNativeCli = out.contenders['native-cli'] ? round(bytes / 1e3 / out.contenders['native-cli'].wallMs, 1) : null;

  // Cross-checks: every contender saw the same mesh.
  const C = out.contenders;
  const ref = C.native || C['native-cli'];
  if (ref) {
    const agree = (name, a, b) => { if (a !== undefined && a !== null && b !== undefined && b !== null) out.checks[name] = a === b; };
    for (const k of ['native-cli', 'wasm-read', 'wasm-full', 'wasm-view', 'wasm-full-kept', 'three', 'three-kept', 'three-halfedge']) if (C[k]) agree(`${k} vertices`, C[k].vertices, ref.vertices);
    for (const k of ['native-cli', 'wasm-full', 'wasm-view', 'wasm-full-kept']) if (C[k]) agree(`${k} holes`, C[k].holes, ref.holes);
    if (C.admesh) agree('admesh disconnected edges = boundary edges', C.admesh.disconnectedEdges, ref.boundaryEdges);
    if (C['three-halfedge']) agree('three-mesh-halfedge boundary half-edges = boundary edges', C['three-halfedge'].boundaryHalfedges, ref.boundaryEdges);
    for (const [name, v] of Object.entries(out.checks)) if (!v) errors.push(`${c.id}: check failed: ${name}`);
  }

  // Ratios (speed-ups are "how many times faster"; wasm/native is a slowdown factor).
  const t = (k) => (C[k] ? C[k].timeMs : null);
  const div = (a, b) => (a && b ? round(a / b, 2) : null);
  const R = out.ratios;
  R.wasmFullVsThree = div(t('three'), t('wasm-full'));
  // Both in a Node whose allocator keeps freed memory (contenders.mjs, KEPT_ENV): the copies
  // without fresh pages, against three.js in the same setting.
  R.wasmFullVsThreeKept = div(t('three-kept'), t('wasm-full-kept'));
  R.wasmFullVsThreeFirstCall = C.three && C['wasm-full'] ? div(C.three.firstMs, C['wasm-full'].firstMs) : null;
  if (C['three-halfedge']) {
    const he = C['three-halfedge'];
    R.wasmFullVsThreeHalfedge = div(he.timeMs ?? he.lowerBoundMs, t('wasm-full'));
    if (he.timeMs === null) R.wasmFullVsThreeHalfedgeIsLowerBound = true;
  }
  R.wasmFullOverNative = C.native ? div(t('wasm-full'), C.native.warm.totalMs) : null;
  R.wasmViewOverNative = C.native ? div(t('wasm-view'), C.native.warm.totalMs) : null;
  R.wasmFullOverNativeCpu = C.native && C['wasm-full'] ? div(C['wasm-full'].warmCpuMs, C.native.warm.cpuMs) : null;
  R.wasmFullOverNativeFirstCall = C.native && C['wasm-full'] ? div(C['wasm-full'].firstMs, C.native.first.totalMs) : null;
  R.wasmReadOverNativeRead = C.native ? div(t('wasm-read'), C.native.warm.readMs) : null;
  R.wasmFirstOverWarm = C['wasm-full'] ? div(C['wasm-full'].firstMs, C['wasm-full'].warmMs) : null;
  R.nativeCliVsAdmesh = div(t('admesh'), t('native-cli'));
  // Issue 24: the CLI on the machine's cores against --threads 1 (same run, alternated).
  // The CLI's default since stop 41 is --threads 0, every core; nativeCliVsAdmesh keeps the
  // one-thread figure of the runs before, nativeCliDefaultVsAdmesh is the default's.
  R.nativeCliDefaultVsAdmesh = C['native-cli'] ? div(t('admesh'), C['native-cli'].allThreadsWallMs) : null;
  R.nativeCliThreadsSpeedup = C['native-cli'] && C['native-cli'].allThreadsWallMs ? div(C['native-cli'].wallMs, C['native-cli'].allThreadsWallMs) : null;
  R.nativeCliVsAdmeshCpu = C.admesh && C['native-cli'] ? div(C.admesh.cpuMs, C['native-cli'].cpuMs) : null;
  R.nativeInProcessVsAdmesh = C.native ? div(t('admesh'), C.native.warm.totalMs) : null;
  R.nativeCliBytesPerTriangle = C['native-cli'] ? C['native-cli'].bytesPerTriangle : null;
  R.fullTopologyStreamedBytesPerTriangle = C.native ? C.native.fullTopologyStreamedBytesPerTriangle ?? null : null;
  R.wasmHeapBytesPerTriangle = C['wasm-full'] ? C['wasm-full'].heapBytesPerTriangle : null;
  R.inputBytesPerTriangle = out.triangles ? round(bytes / out.triangles, 1) : null;
  return out;
}

// ---------------------------------------------------------------------------
// Targets (issue 7), evaluated at 1M triangles and up when the run has them, else at the
// largest size it has (then flagged: the targets are stated at 1M).

export function evaluateTargets(results) {
  const sizeRank = (s) => SIZES[s];
  function targetSet(filter) {
    const rs = results.filter(filter);
    if (!rs.length) return { rs, atSize: null };
    const big = rs.filter((r) => sizeRank(r.size) >= SIZES['1M']);
    if (big.length) return { rs: big, atSize: '1M+' };
    const maxSize = rs.reduce((m, r) => (sizeRank(r.size) > sizeRank(m) ? r.size : m), rs[0].size);
    return { rs: rs.filter((r) => r.size === maxSize), atSize: maxSize };
  }
  function target(name, goal, op, filter, value, { exactSize = null, note = null } = {}) {
    const { rs, atSize } = exactSize
      ? (() => { const x = results.filter((r) => filter(r) && r.size === exactSize); return x.length ? { rs: x, atSize: exactSize } : targetSet(filter); })()
      : targetSet(filter);
    const vals = rs.map((r) => ({ case: r.id, value: value(r) })).filter((v) => v.value !== null && v.value !== undefined);
    if (!vals.length) return { name, goal, op, met: null, values: [], atSize, note };
    const worst = op === '>=' ? Math.min(...vals.map((v) => v.value)) : Math.max(...vals.map((v) => v.value));
    const met = op === '>=' ? worst >= goal : worst <= goal;
    return { name, goal, op, met, worst, values: vals, atSize, note };
  }
  const bin = (r) => r.format === 'binary';
  return [
    target('wasm full pipeline vs three.js parse+mergeVertices (x faster)', 20, '>=', bin, (r) => r.ratios.wasmFullVsThree, { exactSize: '1M' }),
    target('the same, both in a Node whose allocator keeps freed memory (GLIBC_TUNABLES, bench/contenders.mjs KEPT_ENV)', 20, '>=', bin, (r) => r.ratios.wasmFullVsThreeKept, { exactSize: '1M' }),
    target('wasm full pipeline vs three.js + three-mesh-halfedge (x faster)', 50, '>=', (r) => bin(r) && HALFEDGE_SIZES.includes(r.size), (r) => r.ratios.wasmFullVsThreeHalfedge, { exactSize: '1M' }),
    target('wasm full / native in-process, ordered (slowdown)', 1.2, '<=', (r) => bin(r) && r.order === 'ordered', (r) => r.ratios.wasmFullOverNative),
    target('wasm full / native in-process, shuffled (slowdown)', 1.2, '<=', (r) => bin(r) && r.order === 'shuffled', (r) => r.ratios.wasmFullOverNative),
    target('native whole-process vs admesh -e, ordered (x faster)', 2, '>=', (r) => bin(r) && r.order === 'ordered', (r) => r.ratios.nativeCliVsAdmesh),
    target('native whole-process vs admesh -e, shuffled (x faster)', 5, '>=', (r) => bin(r) && r.order === 'shuffled', (r) => r.ratios.nativeCliVsAdmesh),
    target('ASCII: native whole-process vs admesh -e (x faster)', 3, '>=', (r) => r.format === 'ascii', (r) => r.ratios.nativeCliVsAdmesh),
    // Issue 24: `stltopo info` as users run it (the machine's cores) against admesh -e.
    target('native whole-process, default threads, vs admesh -e, ordered (x faster; issue 24)', 3, '>=', (r) => bin(r) && r.order === 'ordered', (r) => r.ratios.nativeCliDefaultVsAdmesh),
    target('native whole-process, default threads, vs admesh -e, shuffled (x faster; issue 24)', 10, '>=', (r) => bin(r) && r.order === 'shuffled', (r) => r.ratios.nativeCliDefaultVsAdmesh),
    target('peak RSS above idle, full topology (prev and face included), streamed, C++ API (bytes/triangle)', 110, '<=', bin, (r) => r.ratios.fullTopologyStreamedBytesPerTriangle),
    target('peak RSS above idle, `stltopo info --json` (report-only topology, input mapped and dropped as read) (bytes/triangle)', 110, '<=', bin, (r) => r.ratios.nativeCliBytesPerTriangle),
  ];
}

// ---------------------------------------------------------------------------
// Tables

const f = (x, d = 1) => (x === null || x === undefined ? '–' : Number(x).toFixed(d));
const ms = (x) => (x === null || x === undefined ? '–' : x >= 100 ? x.toFixed(0) : x >= 10 ? x.toFixed(1) : x.toFixed(2));
const mt = (n) => (n >= 1e6 ? `${(n / 1e6).toFixed(n % 1e6 ? 2 : 0)}M` : n >= 1e3 ? `${Math.round(n / 1e3)}k` : String(n));
function table(head, rows) {
  const lines = [`| ${head.join(' | ')} |`, `|${head.map((_, i) => (i === 0 ? ':--' : '--:')).join('|')}|`];
  for (const r of rows) lines.push(`| ${r.join(' | ')} |`);
  return lines.join('\n');
}
const C = (r, k) => r.contenders[k] || null;
const heCell = (r) => {
  const h = C(r, 'three-halfedge');
  if (!h) return 'n/a';
  return h.timeMs === null ? `> ${ms(h.lowerBoundMs)} (cap)` : ms(h.timeMs);
};

export function reportTables({ env, results, writes, targets }) {
  const md = [];
  md.push(`## stltopo benchmark — ${env.date.slice(0, 10)}`);
  md.push('');
  md.push(`Machine: ${env.machine.cpu}, ${env.machine.cores} cores, ${env.machine.memoryGiB} GiB, ${env.machine.distro || env.machine.os}; ` +
    `Node ${env.versions.node}, ${env.versions.cxx}, ${env.versions.emcc || 'emcc ?'}, three ${env.versions.three}, ` +
    `three-mesh-halfedge ${env.versions['three-mesh-halfedge']}, admesh ${env.versions.admesh}. ` +
    `Medians of ${opt.reps} alternating repetitions (one child process per measurement, one at a time); in-process "warm" = median of the calls after the first ` +
    `in the same process (${opt.warm}; native at 100k and below: 5; fewer when a call takes over 10 s); whole-process figures at 100k and below: median of 3 back-to-back runs per repetition. ` +
    `Commit ${env.git.commit ? env.git.commit.slice(0, 10) : '?'}${env.git.dirtySources ? ' (+ uncommitted source changes)' : ''}. Load average at start ${env.machine.loadAverageAtStart.join(', ')}.` +
    (env.memoryFirstTouch.gib > 0 && !env.memoryFirstTouch.failed
      ? ` Memory first touch on this machine (${env.memoryFirstTouch.gib} GiB, one process): ${env.memoryFirstTouch.firstTouchGiBps} GiB/s, second pass ${env.memoryFirstTouch.secondPassGiBps} GiB/s; whole-process and first-call figures pay the first-touch rate for the memory they use.`
      : ''));
  md.push('');
  md.push('### Time (ms; lower is better)');
  md.push('');
  md.push(table(
    ['case', 'triangles', 'native in-process (warm)', 'native `info --json` (process; --threads 1 / the default, --threads 0: all cores)', 'wasm topology:false first / warm', 'wasm full first / warm', 'wasm full, view: true (warm)', 'three.js parse+merge', 'wasm full / three.js, freed memory kept (warm)', 'three.js + halfedge', '`admesh -e` (process)'],
    results.map((r) => [
      r.id, mt(r.triangles || 0),
      C(r, 'native') ? ms(C(r, 'native').warm.totalMs) : '–',
      C(r, 'native-cli') ? `${ms(C(r, 'native-cli').wallMs)} / ${C(r, 'native-cli').allThreadsWallMs != null ? ms(C(r, 'native-cli').allThreadsWallMs) : '–'}` : '–',
      C(r, 'wasm-read') ? `${ms(C(r, 'wasm-read').firstMs)} / ${ms(C(r, 'wasm-read').warmMs)}` : '–',
      C(r, 'wasm-full') ? `${ms(C(r, 'wasm-full').firstMs)} / ${ms(C(r, 'wasm-full').warmMs)}` : '–',
      C(r, 'wasm-view') ? ms(C(r, 'wasm-view').timeMs) : '–',
      C(r, 'three') ? ms(C(r, 'three').timeMs) : '–',
      C(r, 'wasm-full-kept') || C(r, 'three-kept') ? `${C(r, 'wasm-full-kept') ? ms(C(r, 'wasm-full-kept').timeMs) : '–'} / ${C(r, 'three-kept') ? ms(C(r, 'three-kept').timeMs) : '–'}` : '–',
      heCell(r),
      C(r, 'admesh') ? ms(C(r, 'admesh').wallMs) : '–',
    ]),
  ));
  md.push('');
  md.push('Freed memory kept: the same wasm full and three.js measurements (the 1M binary cases) in a Node started with ' +
    '`GLIBC_TUNABLES=glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=4294967295`, so that glibc serves the JS arrays from ' +
    'its heap and keeps the pages they free for the next call: what the copies out of wasm memory cost without fresh pages.');
  md.push('');
  md.push('### stltopo stages, native in-process (ms, warm; first call in parentheses) and throughput');
  md.push('');
  md.push(table(
    ['case', 'read (parse + weld)', 'topology (pairing + holes + vertex loops)', 'stats (report)', 'total', 'M tri/s in-process', 'M tri/s wasm full', 'M tri/s process', 'MB/s process', 'wasm full: first read of prev/face/vert in JS'],
    results.filter((r) => C(r, 'native')).map((r) => {
      const n = C(r, 'native');
      return [
        r.id, `${ms(n.warm.readMs)} (${ms(n.first.readMs)})`, `${ms(n.warm.topologyMs)} (${ms(n.first.topologyMs)})`,
        `${ms(n.warm.reportMs)} (${ms(n.first.reportMs)})`, `${ms(n.warm.totalMs)} (${ms(n.first.totalMs)})`,
        f(n.mTrianglesPerSecond, 2), C(r, 'wasm-full') ? f(C(r, 'wasm-full').mTrianglesPerSecond, 2) : '–',
        C(r, 'native-cli') ? f(C(r, 'native-cli').mTrianglesPerSecond, 2) : '–', f(r.mbytesPerSecondNativeCli, 0),
        C(r, 'wasm-full') && C(r, 'wasm-full').derivedHalfedgesMs != null ? ms(C(r, 'wasm-full').derivedHalfedgesMs) : '–',
      ];
    }),
  ));
  md.push('');
  md.push('### Peak memory (bytes per triangle above an idle process; input file: ~50 B/triangle binary)');
  md.push('');
  md.push(table(
    ['case', 'native full topology, streamed (C++ API)', 'native `info --json` RSS', 'wasm full: heap high-water', 'wasm full: Node RSS', 'wasm topology:false: heap', 'three.js RSS', 'three.js + halfedge RSS', 'admesh RSS'],
    results.map((r) => [
      r.id,
      C(r, 'native') && C(r, 'native').fullTopologyStreamedBytesPerTriangle != null ? f(C(r, 'native').fullTopologyStreamedBytesPerTriangle) : '–',
      C(r, 'native-cli') ? f(C(r, 'native-cli').bytesPerTriangle) : '–',
      C(r, 'wasm-full') ? f(C(r, 'wasm-full').heapBytesPerTriangle) : '–',
      C(r, 'wasm-full') ? f(C(r, 'wasm-full').rssBytesPerTriangle) : '–',
      C(r, 'wasm-read') ? f(C(r, 'wasm-read').heapBytesPerTriangle) : '–',
      C(r, 'three') ? f(C(r, 'three').rssBytesPerTriangle) : '–',
      C(r, 'three-halfedge') && C(r, 'three-halfedge').timeMs !== null ? f(C(r, 'three-halfedge').rssBytesPerTriangle) : '–',
      C(r, 'admesh') ? f(C(r, 'admesh').bytesPerTriangle) : '–',
    ]),
  ));
  md.push('');
  md.push('Native full topology: `stltopo_stages FILE --streamed-peak`, which reads FILE through a Reader in 1 MiB chunks and builds the ' +
    'full topology (prev and face included) and the report: its peak RSS minus its RSS before the read. `info --json` builds the report-only ' +
    'topology (no prev and face, TopologyOptions::prevAndFace = false), and so do wasm copies (wasm full). ' +
    'Native CLI and admesh: peak RSS (wait4) minus that of the same program on an 18-triangle file. wasm heap: ' +
    'the WebAssembly.Memory buffer size after the first call (linear memory never shrinks, so this is its ' +
    'high-water mark; the package exposes no allocator peak; it includes the initial 16 MiB), divided by the triangles. Node RSS: peak RSS of the ' +
    'child process minus its RSS before reading the file (it holds the whole input and the JS copies of the output).');
  md.push('');
  if (writes) {
    md.push(`### Writing STL (${writes.case}, ${writes.triangles} triangles; MB/s of output, median of ${opt.reps})`);
    md.push('');
    const w = (x) => `${f(x.mbPerSecond, 0)} MB/s (${f(x.ms, 0)} ms)`;
    md.push(table(['writer', 'binary', 'ASCII'], [
      ['stltopo native (writeStl into a counting sink)', w(writes.native.binary), w(writes.native.ascii)],
      ['stltopo wasm (Node, toStl)', w(writes.wasm.binary), w(writes.wasm.ascii)],
      ['three.js STLExporter.parse', w(writes.threeExporter.binary), w(writes.threeExporter.ascii)],
    ]));
    md.push('');
  }
  md.push('### Ratios');
  md.push('');
  md.push(table(
    ['case', 'wasm full vs three.js (x)', '(both with freed memory kept)', 'wasm full vs three+halfedge (x)', 'wasm full / native', '(CPU time)', 'wasm view / native', 'wasm read / native read', 'wasm first / warm', 'native process vs admesh (x, wall)', '(x, CPU time)', 'native in-process vs admesh (x)'],
    results.map((r) => {
      const R = r.ratios;
      return [
        r.id, f(R.wasmFullVsThree), f(R.wasmFullVsThreeKept), R.wasmFullVsThreeHalfedge === undefined ? 'n/a' : `${R.wasmFullVsThreeHalfedgeIsLowerBound ? '> ' : ''}${f(R.wasmFullVsThreeHalfedge)}`,
        f(R.wasmFullOverNative, 2), f(R.wasmFullOverNativeCpu, 2), f(R.wasmViewOverNative, 2), f(R.wasmReadOverNativeRead, 2), f(R.wasmFirstOverWarm, 2), f(R.nativeCliVsAdmesh, 2), f(R.nativeCliVsAdmeshCpu, 2), f(R.nativeInProcessVsAdmesh, 2),
      ];
    }),
  ));
  md.push('');
  md.push('### Targets (issues 7 and 24)');
  md.push('');
  md.push(table(
    ['target', 'goal', 'worst', 'status', 'values'],
    targets.map((t) => [
      t.name, `${t.op} ${t.goal}`, f(t.worst, 2),
      t.met === null ? 'not measured' : `${t.met ? 'met' : 'MISSED'}${t.atSize && t.atSize !== '1M' && t.atSize !== '1M+' ? ` (at ${t.atSize} only)` : ''}`,
      t.values.map((v) => `${v.case} ${f(v.value, 2)}`).join('; '),
    ]),
  ));
  return md;
}

export function appendEditsTable(md, edits, editCount) {
  const editCols = Object.keys(edits);
  if (editCols.length) {
    md.push('');
    md.push(`### Edits per CPU second (EditableMesh; ${editCount} of each kind on random elements; bench/edits.cpp, bench/edits.mjs)`);
    md.push('');
    const ops = Object.keys(edits[editCols[0]]);
    md.push(table(['edit', ...editCols], ops.map((op) => [op, ...editCols.map((k) => {
      const xs = edits[k][op] ?? [];
      return xs.length ? `${Math.round(median(xs.map((e) => e.perCpuSecond)) / 1000)}k` : 'n/a';
    })])));
  }
}

export function resultJson({ writes, env, t0run, idle, cost, results, edits, targets }) {
  return {
    benchmark: 'stltopo issue 7',
    writes,
    environment: { ...env, loadAverageAtEnd: os.loadavg().map((x) => round(x, 2)), durationSec: round((Date.now() - t0run) / 1000, 1) },
    idleRssKiB: idle,
    costSec: Object.fromEntries(Object.entries(cost).map(([k, v]) => [k, round(v, 1)])),
    method: {
      time: 'wall-clock medians over alternating repetitions (one child process per measurement, one at a time)',
      native: 'stltopo_stages: readStl + buildTopology + infoJson on the file bytes in memory; first call and warm calls in the same process',
      nativeCli: 'procstat (fork/exec/wait4) of `stltopo info --json FILE`: wall time from fork to exit; peak RSS minus the idle run; at 100k and below each repetition is the median of 3 runs',
      wasm: 'Node: loadStl(bytes, { topology }) from the package (dist/), arrays copied out (default); first call after instantiation, then warm calls',
      three: 'STLLoader.parse(ArrayBuffer) + deleteAttribute("normal") + BufferGeometryUtils.mergeVertices; + HalfedgeDS.setFromGeometry for three-halfedge',
      admesh: 'procstat of `admesh -e FILE`',
      wasmHeap: 'WebAssembly.Memory buffer byteLength after the first call (high-water mark of linear memory; includes the initial heap)',
    },
    cases: results,
    edits: Object.fromEntries(Object.entries(edits).map(([k, v]) => [k, Object.fromEntries(Object.entries(v).map(([op, xs]) => [op, {
      perCpuSecond: Math.round(median(xs.map((e) => e.perCpuSecond))), attempts: xs[0].attempts, done: xs[0].done }]))])),
    targets,
    errors,
  };
}
