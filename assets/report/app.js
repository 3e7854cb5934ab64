// voussoir's HTML report (src/viz/html/mod.rs writes the page and its data). Axes: the glTF
// files are y-up (voussoir's z-up x, y, z is x, z, −y there); the report's JSON is in voussoir's.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { mergeGeometries } from 'three/addons/utils/BufferGeometryUtils.js';

const data = JSON.parse(document.getElementById('voussoir-data').textContent);
/** The JSON report, read when first asked for (a large design's takes a quarter second). */
let reportRead = null;
const report = () => reportRead ??= globalThis.voussoirAsset('report.json').then((b) => JSON.parse(new TextDecoder().decode(b)));
const $ = (id) => document.getElementById(id);
const yUp = (p) => new THREE.Vector3(p[0], p[2], -p[1]);

/** The one WebGL renderer both views draw with, off the page: each view copies its picture
 *  into its own canvas. One context and one set of compiled shaders (a software renderer
 *  takes a noticeable fraction of a second for each). */
const gl = new THREE.WebGLRenderer({ antialias: true });

/** One 3D view in `container`: its canvas, a camera framed on what it shows, orbit controls. */
class View {
  constructor(container) {
    this.container = container;
    this.canvas = document.createElement('canvas');
    this.picture = this.canvas.getContext('2d');
    container.appendChild(this.canvas);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xffffff);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.set(1, 2, 1.5);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.addEventListener('change', () => this.render());
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }
  resize() {
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    this.canvas.width = Math.round(w * window.devicePixelRatio);
    this.canvas.height = Math.round(h * window.devicePixelRatio);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }
  /** Frames `object`: seen from the front (voussoir's −y), a little from the right and above. */
  frame(object) {
    const box = new THREE.Box3().setFromObject(object);
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const radius = box.getSize(new THREE.Vector3()).length() / 2;
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2)) * 1.05;
    const dir = new THREE.Vector3(0.35, 0.3, 1).normalize();
    this.camera.position.copy(centre).addScaledVector(dir, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.render();
  }
  render() {
    const { width, height } = this.canvas;
    const size = gl.getDrawingBufferSize(new THREE.Vector2());
    if (size.x !== width || size.y !== height) gl.setSize(width, height, false); // device pixels
    gl.render(this.scene, this.camera);
    this.picture.drawImage(gl.domElement, 0, 0);
  }
  /** Where world point `p` is on the page, CSS pixels. */
  toPage(p) {
    const v = p.clone().project(this.camera);
    const r = this.canvas.getBoundingClientRect();
    return { x: r.left + (v.x + 1) / 2 * r.width, y: r.top + (1 - v.y) / 2 * r.height };
  }
  /** The objects under the page point (x, y), nearest first. */
  pick(x, y, objects) {
    const r = this.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2((x - r.left) / r.width * 2 - 1, -((y - r.top) / r.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    return ray.intersectObjects(objects, true);
  }
}

/** Lambert shading in place of the glTF's physically based materials: the same colours and
 *  transparency, and a shader that a software renderer compiles several times faster (the
 *  report must open quickly without a GPU). Unlit (diagram) materials stay as they are. */
function lambert(root) {
  const swapped = new Map();
  root.traverse((o) => {
    if (!o.isMesh || !o.material.isMeshStandardMaterial) return;
    if (!swapped.has(o.material)) {
      const m = o.material;
      swapped.set(m, new THREE.MeshLambertMaterial({
        color: m.color, opacity: m.opacity, transparent: m.transparent, side: m.side,
        depthWrite: m.depthWrite, vertexColors: m.vertexColors, name: m.name }));
    }
    o.material = swapped.get(o.material);
  });
  return root;
}

const loader = new GLTFLoader();
const gltfCache = new Map();
async function gltf(asset) {
  if (!gltfCache.has(asset)) {
    gltfCache.set(asset, loader.parseAsync(await globalThis.voussoirAsset(asset), '').then((g) => { lambert(g.scene); return g; }));
  }
  return gltfCache.get(asset);
}

const number = (x, unit) => (x === null || x === undefined) ? '—' : `${Number(x).toPrecision(6)} ${unit}`;
const percent = (x) => (x === null || x === undefined) ? '—' : `${(100 * x).toFixed(1)} %`;

// ---- the header, the notes, the panel, the plots ----------------------------------------
$('verdict').textContent = data.verdict;
$('verdict').style.color = data.verdict_colour;
$('scene').textContent = data.scene;
for (const note of data.notes) {
  const p = document.createElement('p');
  p.textContent = note;
  $('notes').appendChild(p);
}
$('panel-text').textContent = data.panel;
for (const plot of data.plots) {
  const fig = document.createElement('figure');
  fig.innerHTML = plot.svg;
  const cap = document.createElement('figcaption');
  cap.textContent = plot.title;
  fig.appendChild(cap);
  $('plots').appendChild(fig);
}

// ---- the design and its diagrams ----------------------------------------------------------
const design = new View($('design-view'));
const designs = {};
let mode = null;
let blocksShown = true;

/** One mesh per material in place of the glTF's mesh per block and per interface (a large
 *  design's first frame spent its time on a draw call each); each merged mesh keeps its parts'
 *  first triangles and tags ({block} or {interface}) for picking. */
function merged(root) {
  root.updateMatrixWorld(true);
  const byMaterial = new Map();
  root.traverse((o) => {
    if (!o.isMesh) return;
    const tag = o.userData.interface !== undefined ? { interface: o.userData.interface } : { block: o.userData.block };
    if (!byMaterial.has(o.material)) byMaterial.set(o.material, []);
    byMaterial.get(o.material).push({ geometry: o.geometry.clone().applyMatrix4(o.matrixWorld), tag });
  });
  const out = new THREE.Group();
  for (const [material, parts] of byMaterial) {
    const mesh = new THREE.Mesh(mergeGeometries(parts.map((p) => p.geometry)), material);
    let first = 0;
    mesh.userData.parts = parts.map((p) => {
      const part = { first, tag: p.tag };
      first += p.geometry.attributes.position.count / 3;
      return part;
    });
    mesh.userData.blocks = parts[0].tag.block !== undefined;
    out.add(mesh);
  }
  return out;
}

/** The tag of the part of a merged mesh that triangle `face` belongs to (else of the object). */
function tagOf(hit) {
  const parts = hit.object.userData.parts;
  if (parts) {
    let lo = 0, hi = parts.length - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (parts[mid].first <= hit.faceIndex) lo = mid; else hi = mid - 1;
    }
    return parts[lo].tag;
  }
  let o = hit.object;
  while (o && o.userData.interface === undefined && o.userData.block === undefined) o = o.parent;
  return o && o.userData;
}

/** The resultant arrows of the vectors diagram: one per loaded interface, length by force. */
function arrows(size, interfaces) {
  const group = new THREE.Group();
  const largest = Math.max(0, ...interfaces.map((r) => Math.hypot(...r.resultant)));
  for (const r of interfaces) {
    const f = Math.hypot(...r.resultant);
    if (!r.resultant_point || !(largest > 0) || f < 1e-6 * largest) continue;
    const length = 0.2 * size * f / largest;
    const dir = yUp(r.resultant).normalize();
    const arrow = new THREE.ArrowHelper(dir, yUp(r.resultant_point).addScaledVector(dir, -length), length, 0x222222, 0.25 * length, 0.12 * length);
    arrow.userData.interface = r.index;
    group.add(arrow);
  }
  return group;
}

async function showMode(name) {
  mode = name;
  const source = name === 'vectors' ? 'compression' : name;
  if (!designs[name]) {
    const diagram = data.diagrams.find((d) => d.name === source);
    const root = merged((await gltf(diagram.asset)).scene);
    if (name === 'vectors') {
      const size = new THREE.Box3().setFromObject(root).getSize(new THREE.Vector3()).length();
      root.add(arrows(size, (await report()).interfaces));
    }
    designs[name] = { root, legend: diagram.legend };
  }
  for (const child of [...design.scene.children]) if (child.userData.design) design.scene.remove(child);
  designs[name].root.userData.design = true;
  design.scene.add(designs[name].root);
  showBlocks(blocksShown);
  $('legend').innerHTML = '';
  for (const [colour, label] of designs[name].legend) {
    const swatch = document.createElement('span');
    swatch.className = 'swatch';
    swatch.style.background = colour;
    $('legend').append(swatch, label);
  }
  if (name === 'vectors') $('legend').append(' — arrows: the interfaces\' resultants, length by force');
  for (const b of document.querySelectorAll('#modes button')) b.classList.toggle('on', b.dataset.mode === name);
  design.render();
}

function showBlocks(shown) {
  blocksShown = shown;
  for (const d of Object.values(designs)) d.root.traverse((o) => { if (o.userData.blocks) o.visible = shown; });
  $('blocks-toggle').textContent = shown ? 'hide' : 'show';
  design.render();
}

for (const name of ['compression', 'friction', 'vectors']) {
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = name;
  b.dataset.mode = name;
  b.addEventListener('click', () => showMode(name));
  $('modes').appendChild(b);
}
$('blocks-toggle').addEventListener('click', () => showBlocks(!blocksShown));

/** What a click on the design shows: the interface's forces, or the block's mass. */
function describe(hit, { interfaces, blocks }) {
  if (hit.interface !== undefined) {
    const r = interfaces[hit.interface];
    return [`interface ${r.index}: ${r.a} | ${r.b}`,
      `normal force ${number(r.normal_force, 'N')}`,
      `compression  ${number(r.compression, 'N')}`,
      `tension      ${number(r.tension, 'N')}`,
      `friction     ${number(r.friction, 'N')}`,
      `friction use ${percent(r.friction_utilization)} of μ·compression`,
      `area         ${number(r.area, 'm²')}`].join('\n');
  }
  const b = blocks[hit.block];
  return [`block ${b.name}${b.support ? ' (support)' : ''}`,
    `mass    ${number(b.mass, 'kg')}`,
    `volume  ${number(b.volume, 'm³')}`,
    `centroid ${b.centroid.map((c) => c.toPrecision(4)).join(', ')} m`].join('\n');
}

let down = null;
design.canvas.addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY }; });
design.canvas.addEventListener('pointerup', async (e) => {
  if (!down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4) return;
  const hits = design.pick(e.clientX, e.clientY, [designs[mode].root]).filter((h) => h.object.visible);
  const tagged = hits.map(tagOf).filter(Boolean);
  // An interface seen through the translucent block in front of it is what was meant.
  const hit = tagged.find((u) => u.interface !== undefined) || tagged[0];
  if (!hit) {
    $('info').textContent = 'Nothing there: click a block or an interface.';
    return;
  }
  report().then((r) => { $('info').textContent = describe(hit, r); });
});

// ---- the motions --------------------------------------------------------------------------
const motionView = new View($('motion-view'));
const player = { motion: null, mixer: null, duration: 0, time: 0, playing: true, last: null };

async function showMotion(k) {
  const m = data.motions[k];
  for (const b of document.querySelectorAll('#tabs button')) b.classList.toggle('on', Number(b.dataset.k) === k);
  const g = await gltf(m.asset);
  for (const child of [...motionView.scene.children]) if (child.userData.motion) motionView.scene.remove(child);
  g.scene.userData.motion = true;
  const moved = new Set(m.moved);
  g.scene.traverse((o) => {
    if (o.isMesh && moved.has(o.userData.block)) {
      o.material = o.material.clone();
      o.material.color.setStyle(data.moved_colour);
    }
  });
  motionView.scene.add(g.scene);
  player.motion = m;
  player.mixer = new THREE.AnimationMixer(g.scene);
  const clip = g.animations[0];
  player.duration = clip ? clip.duration : 0;
  if (clip) player.mixer.clipAction(clip).play();
  player.time = 0;
  player.mixer.setTime(0);
  motionView.frame(g.scene);
  $('caption').textContent = m.caption;
  setTime(0);
}

function setTime(t) {
  player.time = t;
  if (player.mixer) player.mixer.setTime(t);
  $('clock').textContent = `${t.toFixed(2)} s`;
  $('scrub').value = player.duration > 0 ? Math.round(1000 * t / player.duration) : 0;
  motionView.render();
}

function tick(now) {
  if (player.playing && player.mixer && player.duration > 0) {
    const dt = player.last === null ? 0 : (now - player.last) / 1000;
    setTime((player.time + dt) % player.duration);
  }
  player.last = now;
  requestAnimationFrame(tick);
}

function setPlaying(playing) {
  player.playing = playing;
  $('play').textContent = playing ? 'pause' : 'play';
}
$('play').addEventListener('click', () => setPlaying(!player.playing));
$('scrub').addEventListener('input', () => { setPlaying(false); setTime(player.duration * $('scrub').value / 1000); });

data.motions.forEach((m, k) => {
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = m.title;
  b.dataset.k = k;
  b.addEventListener('click', () => showMotion(k));
  $('tabs').appendChild(b);
});

// ---- start, and what a test (or a curious user) can ask the page ------------------------
// Marks (performance.getEntriesByType('mark')): what the page's start spends its time on.
/** The ground plane z = 0 (voussoir's), when the design stands on it: a disc under the design,
 *  in both views, added after the design is framed (it does not count in the framing). A
 *  backdrop: drawn first and writing no depth, it hides nothing (the arrows into the ground,
 *  the ground's own joints). */
function ground(view, around) {
  const box = new THREE.Box3().setFromObject(around);
  const centre = box.getCenter(new THREE.Vector3());
  const radius = 0.55 * box.getSize(new THREE.Vector3()).length();
  const disc = new THREE.Mesh(new THREE.CircleGeometry(radius, 64),
    new THREE.MeshBasicMaterial({ color: 0xe6e2d8, side: THREE.DoubleSide, depthWrite: false }));
  disc.renderOrder = -1;
  disc.rotation.x = -Math.PI / 2;
  disc.position.set(centre.x, 0, centre.z);
  view.scene.add(disc);
  view.render();
}

async function start() {
  await showMode(data.first);
  design.frame(designs[data.first].root);
  if (data.ground) ground(design, designs[data.first].root);
  performance.mark('voussoir:design');
  window.voussoir.shownAt = performance.now();
  if (data.solved === 0) {
    const empty = document.createElement('div');
    empty.className = 'overlay';
    empty.textContent = data.detected === 0 ? 'No interfaces: no forces to draw'
      : `No forces: ${data.detected} interface(s), but nothing holds the design, so none were solved`;
    $('design-view').appendChild(empty);
  }
  if (data.motions.length > 0) {
    await showMotion(0);
    if (data.ground) ground(motionView, designs[data.first].root);
    performance.mark('voussoir:motion');
  } else {
    $('motion-view').innerHTML = '<div class="empty">No motion in this report: add --robustness, --dynamic or --settle.</div>';
    for (const id of ['play', 'scrub']) $(id).disabled = true;
  }
  requestAnimationFrame(tick);
  $('status').textContent = 'ready';
  window.voussoir.readyAt = performance.now();
  window.voussoir.ready = true;
}

/** The page point of a block's centroid or an interface's resultant point (else its centroid). */
async function onPage(kind, index) {
  const { interfaces, blocks } = await report();
  if (kind === 'interface') {
    const r = interfaces[index];
    const n = r.vertices.length;
    const p = r.resultant_point || [0, 1, 2].map((k) => r.vertices.reduce((s, v) => s + v.position[k], 0) / n);
    return design.toPage(yUp(p));
  }
  return design.toPage(yUp(blocks[index].centroid));
}

/** Page rectangles of the motion pane's moved blocks now: [left, top, right, bottom]. */
function movingRects() {
  const rects = [];
  const moved = new Set(player.motion ? player.motion.moved : []);
  motionView.scene.traverse((o) => {
    if (!o.isMesh || !moved.has(o.userData.block)) return;
    const box = new THREE.Box3().setFromObject(o);
    const corners = [0, 1, 2, 3, 4, 5, 6, 7].map((k) => motionView.toPage(new THREE.Vector3(
      k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z)));
    rects.push({ block: o.userData.block, rect: [Math.min(...corners.map((c) => c.x)), Math.min(...corners.map((c) => c.y)), Math.max(...corners.map((c) => c.x)), Math.max(...corners.map((c) => c.y))] });
  });
  return rects;
}

window.voussoir = { ready: false, data, report, onPage, movingRects, setTime, player };
start().catch((e) => {
  $('status').textContent = 'The report could not start: ' + e;
  console.error(e);
});
