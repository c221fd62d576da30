// Two animation CSVs (a header, then numbers) side by side: the largest difference per column, and the frames
// where a difference passes the tolerance. Exit status 1 if any does, or if the headers or frame counts differ.
//
//   node web/tools/compare_csv.mjs native.csv web.csv [--tolerance 1e-4] [--json]
import fs from 'node:fs';

export function readCsv(file) {
  const lines = fs.readFileSync(file, 'utf8').trim().split(/\r?\n/);
  return { header: lines[0].split(','), rows: lines.slice(1).map((line) => line.split(',').map(Number)) };
}

export function compareCsv(a, b, tolerance) {
  if (a.header.join(',') !== b.header.join(',')) return { error: `the headers differ: ${a.header} / ${b.header}` };
  if (a.rows.length !== b.rows.length) return { error: `${a.rows.length} frames against ${b.rows.length}` };
  const columns = a.header.map((name) => ({ name, largest: 0, at: -1 }));
  const over = [];
  for (let r = 0; r < a.rows.length; ++r) {
    for (let c = 0; c < columns.length; ++c) {
      const difference = Math.abs(a.rows[r][c] - b.rows[r][c]);
      if (difference > columns[c].largest) Object.assign(columns[c], { largest: difference, at: r });
      if (difference > tolerance) over.push({ frame: r, column: a.header[c], a: a.rows[r][c], b: b.rows[r][c] });
    }
  }
  return { frames: a.rows.length, columns, over, largest: Math.max(...columns.map((c) => c.largest)) };
}

if (import.meta.url === `file://${process.argv[1]}`) {
  const [fileA, fileB] = process.argv.slice(2);
  const at = process.argv.indexOf('--tolerance');
  const tolerance = at > 0 ? Number(process.argv[at + 1]) : 1e-4;
  const result = compareCsv(readCsv(fileA), readCsv(fileB), tolerance);
  if (process.argv.includes('--json')) console.log(JSON.stringify(result));
  else if (result.error) console.log(result.error);
  else {
    console.log(`${result.frames} frames; largest difference ${result.largest.toExponential(2)}; ` +
                `${result.over.length} values over ${tolerance}`);
    for (const c of result.columns) if (c.largest > tolerance) console.log(`  ${c.name}: ${c.largest.toExponential(2)} (frame ${c.at})`);
    for (const o of result.over.slice(0, 20)) console.log(`  frame ${o.frame} ${o.column}: ${o.a} / ${o.b}`);
  }
  process.exit(result.error || result.over.length ? 1 : 0);
}
