// The web view's shapes (server/web/shapes.js) under node, without a browser: a stacker's body
// with its forks from the site's description, a pallet on its forks, and the pallet its cameras
// detect.
//
// node shapes_test.js [--source SOURCE_DIR]
'use strict';
const assert = require('assert');
const path = require('path');

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const SOURCE = args.source || path.resolve(__dirname, '../..');
const shapes = require(path.join(SOURCE, 'server/web/shapes.js'));

let failures = 0;
function test(name, fn) {
  try {
    fn();
    console.log(`ok   ${name}`);
  } catch (e) {
    failures++;
    console.log(`FAIL ${name}\n${e.stack}`);
  }
}
const near = (a, b, what) => assert.ok(Math.abs(a - b) < 1e-9, `${what}: ${a} != ${b}`);
const nearPoints = (got, want, what) => {
  assert.strictEqual(got.length, want.length, `${what}: ${JSON.stringify(got)}`);
  got.forEach(([x, y], i) => {
    near(x, want[i][0], `${what} x[${i}]`);
    near(y, want[i][1], `${what} y[${i}]`);
  });
};
const xs = (polygon) => polygon.map(([x]) => x);

// config/sites/plant.yaml's stackers as GET /api/site gives them: the 1.7 x 0.748 footprint, and
// the 1.15 m tines, 0.17 m wide and 0.38 m apart, from the footprint's back end.
const footprint = [[0.85, 0.374], [-0.85, 0.374], [-0.85, -0.374], [0.85, -0.374]];
const tine = (c) => [[-0.85, c - 0.085], [0.3, c - 0.085], [0.3, c + 0.085], [-0.85, c + 0.085]];
const stacker = { id: 'st1', type: 'stacker', poly: footprint, forks: [tine(0.19), tine(-0.19)] };

test('placed turns and moves body points to the pose', () => {
  nearPoints(shapes.placed(1, 2, Math.PI / 2, [[1, 0], [0, 1]]), [[1, 3], [0, 2]], 'placed');
});

test('rectangle is centred on its pose with its length along the yaw', () => {
  const r = shapes.rectangle(0, 0, Math.PI / 2, 1.2, 0.8);
  nearPoints(r, [[-0.4, 0.6], [-0.4, -0.6], [0.4, -0.6], [0.4, 0.6]], 'rectangle');
});

test('clipAhead keeps the part of a polygon ahead of a line, with the cut edge on it', () => {
  const chassis = shapes.clipAhead(footprint, 0.3);
  near(Math.min(...xs(chassis)), 0.3, 'cut');
  near(Math.max(...xs(chassis)), 0.85, 'front');
  assert.strictEqual(chassis.length, 4);
  assert.deepStrictEqual(shapes.clipAhead(footprint, -1), footprint, 'a line behind the polygon keeps it whole');
  assert.deepStrictEqual(shapes.clipAhead(footprint, 1), [], 'a line ahead of the polygon keeps nothing');
});

test('a stacker is drawn as its footprint, its chassis ahead of the forks and the two tines', () => {
  const parts = shapes.bodyParts(stacker, 1.7, 0.748);
  assert.strictEqual(parts.footprint, footprint, 'the footprint its fleet declares');
  near(parts.root, 0.3, 'the forks end at the chassis back face');
  assert.strictEqual(parts.forks.length, 2);
  near(Math.min(...xs(parts.chassis)), 0.3, 'chassis back');
  near(Math.max(...xs(parts.chassis)), 0.85, 'chassis front');
});

test('a robot without forks is its footprint, or its rectangle when the site does not know it', () => {
  const forklift = { id: 'fl1', type: 'forklift', poly: footprint };
  const parts = shapes.bodyParts(forklift, 1.7, 0.748);
  assert.strictEqual(parts.chassis, footprint);
  assert.deepStrictEqual(parts.forks, []);
  assert.strictEqual(parts.root, null);
  nearPoints(shapes.bodyParts(undefined, 1.0, 0.5).footprint, [[0.5, 0.25], [-0.5, 0.25], [-0.5, -0.25], [0.5, -0.25]], 'rectangle');
});

test('a pallet on the forks lies along them with its entry face at their root', () => {
  const [x, y] = shapes.palletOnForks(0.3);
  near(x + shapes.EPAL.depth / 2, 0.3, 'entry face');
  near(y, 0, 'centred between the tines');
});

test('a detected pallet is a 1.2 x 0.8 outline at its pose with its entry face ahead of it', () => {
  const { outline, face } = shapes.detectedPallet([2, 1, Math.PI]);
  nearPoints(outline, [[1.4, 0.6], [2.6, 0.6], [2.6, 1.4], [1.4, 1.4]], 'outline');
  // The entry axis points out of the entry face: at yaw pi the face is the west side.
  nearPoints(face, [[1.4, 0.6], [1.4, 1.4]], 'face');
});

test('a waiting robot points at each robot it waits for on the view, and no other robot points', () => {
  const robots = [
    ['fl1', { x: 0, y: 0, traffic: { status: 'WAITING', waiting_for: ['fl2', 'fl9'] } }],
    ['fl2', { x: 1, y: 0, traffic: { status: 'MOVING', waiting_for: ['fl1'] } }],
    ['fl3', { x: 0, y: 1, health: 'lost', traffic: { status: 'WAITING', waiting_for: ['fl1'] } }],
  ];
  const arrows = shapes.waitArrows(robots, 0.1);
  assert.strictEqual(arrows.length, 1, JSON.stringify(arrows));
  assert.deepStrictEqual([arrows[0].from, arrows[0].to], ['fl1', 'fl2']);
  nearPoints([arrows[0].a, arrows[0].b], [[0.1, 0], [0.9, 0]], 'arrow between the two, short of both centres');
});

test('a click inside an obstacle outline hits it, and its label sits at the corners\' mean', () => {
  const l = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]];  // an L, concave at (1, 1)
  assert.ok(shapes.inside(l, { x: 0.5, y: 1.5 }));
  assert.ok(!shapes.inside(l, { x: 1.5, y: 1.5 }), 'the notch of the L is outside');
  assert.ok(!shapes.inside(l, { x: 3, y: 0.5 }));
  assert.deepStrictEqual(shapes.centroid([[0, 0], [2, 0], [2, 2], [0, 2]]), { x: 1, y: 1 });
});

if (failures) {
  console.log(`${failures} failed`);
  process.exit(1);
}
console.log('all passed');
