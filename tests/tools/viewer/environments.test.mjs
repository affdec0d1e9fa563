// Environments in the viewer: 1 s runs of scenes/pipe-elbow.yaml,
// terrain.yaml and mesh-pipe.yaml replay with no console or page errors, and
// their pictures show the environment (pixels of the pipe's or the terrain's
// colour) and the modules (the rotation colour). The walls toggle changes the
// picture; a mesh file that is gone gives a warning naming it and a page
// without it.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { cpSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chainsim, launch, newPage, tempDir, waitFor, cleanup, pngColours, IS_PIPE, IS_TERRAIN, IS_ROTATION } from './util.mjs';

const SCENES = join(dirname(fileURLToPath(import.meta.url)), '..', '..', '..', 'scenes');
let browser, dir;
const runs = {};

before(async () => {
  dir = tempDir('env');
  for (const s of ['pipe-elbow', 'terrain', 'mesh-pipe']) {
    runs[s] = join(dir, s);
    const r = chainsim(['run', join(SCENES, `${s}.yaml`), '--duration', '1', '--out', runs[s], '--quiet']);
    if (r.code !== 0) throw new Error(`chainsim run ${s} failed (${r.code}): ${r.stderr}`);
  }
  browser = await launch();
});
after(async () => {
  await browser?.close();
  cleanup();
});

async function open(run) {
  const r = chainsim(['view', run]);
  assert.equal(r.code, 0, r.stderr);
  const page = await newPage(browser, { width: 1000, height: 700 });
  await page.goto(`file://${join(run, 'replay.html')}#t=0.5`);
  await waitFor(() => page.evaluate(() => window.chainsimViewer?.state.ready), 30000, 'the replay to be ready');
  return { page, stderr: r.stderr };
}

function png(run, name) {
  const out = join(dir, `${name}.png`);
  const r = chainsim(['view', run, '--png', '0.8', '--out', out, '--size', '480x300']);
  assert.equal(r.code, 0, r.stderr);
  return out;
}

const note = (page) => page.evaluate(() => {
  const n = document.querySelector('.cs-note');
  return n.hidden ? '' : n.textContent;
});

for (const [scene, colour, minEnv] of [['pipe-elbow', 'pipe', 3000], ['terrain', 'terrain', 3000], ['mesh-pipe', 'pipe', 3000]]) {
  test(`${scene}: replays without errors; the picture shows the ${colour} and the modules`, async () => {
    const { page, stderr } = await open(runs[scene]);
    assert.doesNotMatch(stderr, /warning/);
    assert.equal(await note(page), '', 'no note about the environment');
    const drawn = await page.evaluate(() => {
      let meshes = 0;
      window.chainsimViewer.scene3d.env.object.traverse((o) => { if (o.isMesh) meshes++; });
      return meshes;
    });
    assert.ok(drawn > 0, 'the environment has meshes');
    await page.click('.cs-play');
    await page.waitForTimeout(300);
    assert.deepEqual(page.problems, []);
    await page.close();
    const c = await pngColours(browser, png(runs[scene], scene),
      { env: colour === 'pipe' ? IS_PIPE : IS_TERRAIN, rotation: IS_ROTATION });
    assert.ok(c.env > minEnv, `only ${c.env} pixels of the ${colour} colour`);
    assert.ok(c.rotation > 1500, `only ${c.rotation} pixels of the rotation colour`);
  });
}

test('the walls toggle: cut away, see-through, solid', async () => {
  const { page } = await open(runs['pipe-elbow']);
  const shot = () => page.locator('.cs-view3d canvas').screenshot();
  const cut = await shot();
  await page.selectOption('.cs-walls', 'glass');
  await page.waitForTimeout(100);
  const glass = await shot();
  assert.notDeepEqual(cut, glass);
  await page.keyboard.press('w');  // glass -> solid
  assert.equal(await page.evaluate(() => window.chainsimViewer.scene3d.wallMode), 'solid');
  // the pipe's axis gives the camera its heading: along +y in the last leg
  const tan = await page.evaluate(() => {
    const s = window.chainsimViewer.scene3d;
    const a = s.env.axisAt(s.focus.clone().set(0.47, 0.4, 0.08));
    return [a.tangent.x, a.tangent.y, a.tangent.z];
  });
  assert.ok(tan[1] > 0.99, `tangent ${tan}`);
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('a mesh file that is gone: a warning naming it, the page without it', async () => {
  const run = join(dir, 'mesh-gone');
  cpSync(runs['mesh-pipe'], run, { recursive: true });
  const scene = JSON.parse(readFileSync(join(run, 'scene.json'), 'utf8'));
  scene.environment.mesh.file = '/nonexistent/gone-pipe.stl';
  scene.environment.mesh.file_as_given = 'meshes/gone-pipe.stl';
  writeFileSync(join(run, 'scene.json'), JSON.stringify(scene));
  const { page, stderr } = await open(run);
  assert.match(stderr, /warning: the mesh file meshes\/gone-pipe\.stl is not there/);
  assert.match(await note(page), /mesh meshes\/gone-pipe\.stl is not drawn/);
  assert.deepEqual(page.problems, []);
  await page.close();
});
