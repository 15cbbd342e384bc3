#!/usr/bin/env node
// Writes the array properties of Mesh and EditableMesh into web/src/index.d.ts and
// docs/JS-API.md from the bindings' array tables (STLTOPO_JS_ARRAYS in bindings/arrays.h,
// read from the built dist/ as _arrayLayout, between the "BEGIN arrays" and "END arrays"
// lines; STLTOPO_JS_EDIT_ARRAYS in bindings/edit_arrays.h, read from the full module as
// _editArrayLayout, between "BEGIN editable arrays" and "END editable arrays"), and the keys of
// TopologyCounts in index.d.ts from the count list (include/stltopo/counts.h, read from the full
// module as _countLayout, between "BEGIN counts" and "END counts").
//   node scripts/gen-api-docs.mjs           rewrite both blocks
//   node scripts/gen-api-docs.mjs --check   exit 1 when a block differs (tests/js/boundary.test.mjs)
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { api } from '../dist/instance.node.js';

const root = fileURLToPath(new URL('../', import.meta.url));
const check = process.argv.includes('--check');

// What the table does not say: the JS groups and when an array is null.
const GROUP_DOC = {
  halfedges: 'Half-edge arrays, length nHalfedges; twin(e) = e ^ 1.',
  loops: 'All boundary loops, flat.',
  problems: 'Per-element problems.',
  defects: 'Every defect with its location, as flat arrays (mesh.defect(kind, i) gives one as an object).',
};
const ABSENT = {
  mesh: null,
  normals: 'null without { normals: true }',
  colors: "null when colorConvention is 'none'",
  topology: 'null with topology: false',
  shells: 'null without { shells: true }',
  indexed: 'null for meshes of loadStl()',
};
// Topology fields are typed by Mesh's parameter: present, null, or either (IfTopology).
const tsType = (when, type) => (when === 'topology' ? `IfTopology<T, ${type}>` : ABSENT[when] ? `${type} | null` : type);
const per = (d) => (d.element === 'loop+1' ? 'nLoops + 1'
  : d.element.endsWith('+1') ? `one more than the ${d.element.slice(0, -2)}s`
    : `${d.width > 1 ? d.width : 1} per ${d.element}`);
const notes = (d) => [
  d.derived ? 'copies rebuild it in JS on first read' : null,
  d.copied ? 'always a copy, also with view: true' : null,
].filter(Boolean);

function dtsBlock(layout) {
  const out = [];
  const groups = new Map();
  for (const d of layout) {
    if (!d.group) {
      const absent = ABSENT[d.when];
      out.push(`  /** ${d.doc} ${per(d)}${absent ? `; ${absent}` : ''}. */`);
      out.push(`  ${d.key}: ${tsType(d.when, d.type)};`);
      continue;
    }
    if (!groups.has(d.group)) {
      const members = [];
      groups.set(d.group, members);
      out.push({ group: d.group, members, when: d.when });
    }
    groups.get(d.group).push(d);
  }
  return out.flatMap((x) => {
    if (typeof x === 'string') return [x];
    const absent = ABSENT[x.when];
    const [open, close] = x.when === 'topology' ? ['IfTopology<T, {', '}>'] : ['{', absent ? '} | null' : '}'];
    return [
      `  /** ${GROUP_DOC[x.group] || ''}${absent ? ` ${absent[0].toUpperCase()}${absent.slice(1)}.` : ''} */`,
      `  ${x.group}: ${open}`,
      ...x.members.flatMap((d) => [`    /** ${d.doc} ${per(d)}. */`, `    ${d.key}: ${d.type};`]),
      `  ${close};`,
    ];
  });
}

function mdBlock(layout) {
  const rows = layout.map((d) => {
    const absent = d.group ? null : ABSENT[d.when]; // a group is null as a whole
    const more = [...notes(d), absent].filter(Boolean);
    return `| \`${d.group ? `${d.group}.` : ''}${d.key}\` | ${d.type} | ${per(d)} | ${d.doc}${more.length ? ` (${more.join('; ')})` : ''} |`;
  });
  return ['| mesh. | type | length | contents |', '| --- | --- | --- | --- |', ...rows];
}

// The EditableMesh's block: every array is a copy made when read after an edit, never null.
function editDtsBlock(layout) {
  const out = [];
  const groups = new Map();
  for (const d of layout) {
    if (!d.group) {
      out.push(`  /** ${d.doc} ${per(d)}. */`, `  readonly ${d.key}: ${d.type};`);
      continue;
    }
    if (!groups.has(d.group)) {
      const members = [];
      groups.set(d.group, members);
      out.push({ group: d.group, members });
    }
    groups.get(d.group).push(d);
  }
  return out.flatMap((x) => (typeof x === 'string' ? [x] : [
    `  /** ${GROUP_DOC[x.group] || ''} */`,
    `  readonly ${x.group}: {`,
    ...x.members.flatMap((d) => [`    /** ${d.doc} ${per(d)}. */`, `    readonly ${d.key}: ${d.type};`]),
    '  };',
  ]));
}

function editMdBlock(layout) {
  const rows = layout.map((d) => `| \`${d.group ? `${d.group}.` : ''}${d.key}\` | ${d.type} | ${per(d)} | ${d.doc} |`);
  return ['| em. | type | length | contents |', '| --- | --- | --- | --- |', ...rows];
}

// TopologyCounts: one number per count of the list.
function countsDtsBlock(counts) {
  return counts.flatMap((c) => [`  /** ${c.doc} */`, `  ${c.name}: number;`]);
}

function replaceBlock(file, lines, open, close) {
  const path = `${root}${file}`;
  const text = readFileSync(path, 'utf8');
  const re = new RegExp(`(^.*${open}.*\\n)([\\s\\S]*?)(^.*${close}.*$)`, 'm');
  if (!re.test(text)) throw new Error(`${file}: no "${open}" ... "${close}" block`);
  const next = text.replace(re, (_, a, _b, c) => `${a}${lines.join('\n')}\n${c}`);
  if (next === text) return true;
  if (check) {
    console.error(`${file}: the array block differs from the bindings' table (run node scripts/gen-api-docs.mjs)`);
    return false;
  }
  writeFileSync(path, next);
  console.log(`gen-api-docs: wrote ${file}`);
  return true;
}

// The full module: the core one carries the table without its doc lines and geometry rows.
const full = await api.internal.getFull();
const { layout, editLayout } = full;
const counts = full.module._countLayout();
const ok = [
  replaceBlock('web/src/index.d.ts', dtsBlock(layout), 'BEGIN arrays', 'END arrays'),
  replaceBlock('docs/JS-API.md', mdBlock(layout), 'BEGIN arrays', 'END arrays'),
  replaceBlock('web/src/index.d.ts', editDtsBlock(editLayout), 'BEGIN editable arrays', 'END editable arrays'),
  replaceBlock('docs/JS-API.md', editMdBlock(editLayout), 'BEGIN editable arrays', 'END editable arrays'),
  replaceBlock('web/src/index.d.ts', countsDtsBlock(counts), 'BEGIN counts', 'END counts'),
].every(Boolean);
process.exitCode = ok ? 0 : 1;
