// Bundles the viewer (src/main.js and what it imports: three.js, uPlot, the
// CSS) with esbuild into one JS and one CSS file, which `chainsim view`
// inlines into replay.html and `chainsim run --live` serves.
//   node build.mjs OUTDIR [NODE_MODULES]
// NODE_MODULES: where `npm ci` installed the dependencies (default: ./node_modules)
import { createRequire } from 'node:module';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const outdir = resolve(process.argv[2] ?? join(here, 'dist'));
const nodeModules = resolve(process.argv[3] ?? join(here, 'node_modules'));
const esbuild = createRequire(join(nodeModules, 'noop.js'))('esbuild');

const result = await esbuild.build({
  entryPoints: { viewer: join(here, 'src', 'main.js') },
  bundle: true,
  minify: true,
  format: 'iife',
  target: ['es2020'],
  outdir,
  nodePaths: [nodeModules],
  legalComments: 'eof',
  logLevel: 'warning',
  metafile: true,
});
const out = result.metafile.outputs;
for (const [f, o] of Object.entries(out)) console.log(`viewer bundle: ${f}: ${(o.bytes / 1024).toFixed(0)} KiB`);
