// The 3D viewer of OUT/report.html. Bundled at build time (esbuild, --format=iife) with three.js,
// GLTFLoader and OrbitControls into one classic script, OUT/viewer/photoscene-viewer.js, so the
// report works from file:// (no module imports, no fetches of local files) and over HTTP.
//
// The glTF comes from OUT/viewer/twin_data.js (window.__psTwinGltf: twin.gltf with its buffer
// and images as data URIs). The page calls
//   PhotosceneViewer.start(container, { views: [...], emitters: [...] })
// views: { name, width, height, fx, fy, cx, cy, world_to_camera: 4x4 rows } (OpenCV camera:
// x right, y down, z forward); emitters: { center, edge_u, edge_v, radiance } rectangles.
// When the twin is loaded and drawn, window.__twinLoaded = true; window.__psViewer exposes the
// camera, goToView(i) and render() (for the browser test).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { RectAreaLightUniformsLib } from 'three/addons/lights/RectAreaLightUniformsLib.js';

function rowMajor4(m) {
  const r = new THREE.Matrix4();
  r.set(m[0][0], m[0][1], m[0][2], m[0][3], m[1][0], m[1][1], m[1][2], m[1][3],
        m[2][0], m[2][1], m[2][2], m[2][3], m[3][0], m[3][1], m[3][2], m[3][3]);
  return r;
}

function setStatus(container, text, isError) {
  let el = container.querySelector('.ps-status');
  if (!el) {
    el = document.createElement('div');
    el.className = 'ps-status';
    container.appendChild(el);
  }
  el.textContent = text;
  el.style.display = text ? '' : 'none';
  if (isError) el.classList.add('ps-error');
}

/** World-space area of a mesh's triangles (m^2). */
function surfaceArea(mesh) {
  const pos = mesh.geometry.getAttribute('position');
  const index = mesh.geometry.getIndex();
  const n = index ? index.count : pos.count;
  const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
  let area = 0;
  for (let i = 0; i + 2 < n; i += 3) {
    const ia = index ? index.getX(i) : i, ib = index ? index.getX(i + 1) : i + 1, ic = index ? index.getX(i + 2) : i + 2;
    a.fromBufferAttribute(pos, ia).applyMatrix4(mesh.matrixWorld);
    b.fromBufferAttribute(pos, ib).applyMatrix4(mesh.matrixWorld);
    c.fromBufferAttribute(pos, ic).applyMatrix4(mesh.matrixWorld);
    area += 0.5 * b.sub(a).cross(c.sub(a)).length();
  }
  return area;
}

function start(container, config) {
  config = config || {};
  const views = config.views || [];
  const gltfJson = window.__psTwinGltf;
  if (!gltfJson) {
    setStatus(container, 'No twin data (viewer/twin_data.js) to show.', true);
    return null;
  }
  // the canvas takes the first view's aspect, so "go to input view" frames what the photo shows
  if (views.length > 0 && views[0].width > 0 && views[0].height > 0) {
    const a = views[0].width / views[0].height;
    container.style.aspectRatio = `${views[0].width} / ${views[0].height}`;
    container.style.height = 'auto';
    container.style.maxWidth = `${Math.round(560 * a)}px`;
  }
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = THREE.ACESFilmicToneMapping;
  renderer.toneMappingExposure = config.exposure || 1.0;
  container.appendChild(renderer.domElement);

  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x1e2226);
  const camera = new THREE.PerspectiveCamera(50, 1, 0.01, 1000);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.enableDamping = false;

  // basic lighting so the textured materials are visible from anywhere, plus the emitters
  scene.add(new THREE.HemisphereLight(0xffffff, 0x3a3530, 1.2));
  scene.add(new THREE.AmbientLight(0xffffff, 0.35));
  RectAreaLightUniformsLib.init();
  const rectLights = [];
  for (const e of config.emitters || []) {
    const u = new THREE.Vector3(...e.edge_u), v = new THREE.Vector3(...e.edge_v);
    const c = new THREE.Vector3(...e.center);
    const rad = e.radiance || [1, 1, 1];
    const peak = Math.max(rad[0], rad[1], rad[2], 1e-6);
    const light = new THREE.RectAreaLight(new THREE.Color(rad[0] / peak, rad[1] / peak, rad[2] / peak),
                                          peak, u.length(), v.length());
    // RectAreaLight emits along its local -z; build the frame x = u, y = v, z = -(u x v)
    const n = new THREE.Vector3().crossVectors(u, v).normalize();
    const basis = new THREE.Matrix4().makeBasis(u.clone().normalize(), v.clone().normalize(), n.clone().negate());
    light.quaternion.setFromRotationMatrix(basis);
    light.position.copy(c).addScaledVector(n, 0.002);
    rectLights.push(light);
  }

  let root = null;
  let needsRender = true;
  const render = () => { needsRender = true; };
  const draw = () => {
    if (needsRender) {
      needsRender = false;
      renderer.render(scene, camera);
    }
    requestAnimationFrame(draw);
  };

  const resize = () => {
    const w = container.clientWidth || 640, h = container.clientHeight || 400;
    renderer.setSize(w, h, true);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  };
  window.addEventListener('resize', resize);
  controls.addEventListener('change', render);

  const overview = () => {
    if (!root) return;
    const box = new THREE.Box3().setFromObject(root);
    const center = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3()).length();
    camera.fov = 45;
    camera.near = size / 1000;
    camera.far = size * 20;
    // above and in front of the room: inward-facing walls between the camera and the room are
    // back faces and are culled, a dollhouse view
    camera.position.copy(center).add(new THREE.Vector3(0.55, 0.85, 1.0).normalize().multiplyScalar(size * 1.05));
    controls.target.copy(center);
    camera.updateProjectionMatrix();
    controls.update();
    render();
  };

  // the input view i: OpenCV camera (x right, y down, z forward) -> three.js (x right, y up,
  // looking along -z); the root node's transform (up -> +Y) applies to the cameras too
  const goToView = (i) => {
    const view = views[i];
    if (!view || !root) return false;
    const c2w = rowMajor4(view.world_to_camera).invert();
    const flip = new THREE.Matrix4().makeScale(1, -1, -1);
    const m = new THREE.Matrix4().multiplyMatrices(root.matrixWorld, c2w).multiply(flip);
    const pos = new THREE.Vector3(), quat = new THREE.Quaternion(), scl = new THREE.Vector3();
    m.decompose(pos, quat, scl);
    camera.position.copy(pos);
    camera.quaternion.copy(quat);
    camera.fov = THREE.MathUtils.radToDeg(2 * Math.atan(view.height / (2 * view.fy)));
    camera.updateProjectionMatrix();
    // orbit about a point ahead of the camera, at the distance of the scene's center
    const forward = new THREE.Vector3(0, 0, -1).applyQuaternion(quat);
    const center = new THREE.Box3().setFromObject(root).getCenter(new THREE.Vector3());
    const d = Math.max(0.5, center.clone().sub(pos).dot(forward));
    controls.target.copy(pos).addScaledVector(forward, d);
    controls.update();
    camera.position.copy(pos);
    camera.quaternion.copy(quat);
    render();
    return true;
  };

  const api = { camera, renderer, scene, controls, goToView, overview, render, views };
  window.__psViewer = api;
  setStatus(container, 'Loading the twin…');
  resize();
  requestAnimationFrame(draw);

  const loader = new GLTFLoader();
  loader.parse(JSON.stringify(gltfJson), '', (gltf) => {
    root = gltf.scene;
    scene.add(root);
    root.updateMatrixWorld(true);
    for (const l of rectLights) {
      l.applyMatrix4(root.matrixWorld);
      scene.add(l);
    }
    // OBJ-part emitters light the room too: a point light at each emissive part
    root.traverse((obj) => {
      if (!obj.isMesh || !obj.material || obj.name.startsWith('emitter_')) return;
      const mat = obj.material;
      if (!mat.emissive || mat.emissive.getHex() === 0) return;
      const box = new THREE.Box3().setFromObject(obj);
      // same flux as the emitting surface: a Lambertian emitter of radiance L and area A sends
      // pi L A, a point light of intensity I sends 4 pi I
      const area = surfaceArea(obj);
      const peak = Math.max(mat.emissive.r, mat.emissive.g, mat.emissive.b) * (mat.emissiveIntensity || 1);
      const color = mat.emissive.clone().multiplyScalar(1 / Math.max(mat.emissive.r, mat.emissive.g, mat.emissive.b));
      const light = new THREE.PointLight(color, peak * area / 4, 0, 2);
      light.position.copy(box.getCenter(new THREE.Vector3()));
      scene.add(light);
    });
    setStatus(container, '');
    overview();
    renderer.render(scene, camera);
    window.__twinLoaded = true;
  }, (err) => {
    setStatus(container, 'Could not load the twin: ' + (err && err.message ? err.message : err), true);
    window.__twinLoadError = String(err && err.message ? err.message : err);
  });
  return api;
}

window.PhotosceneViewer = { start, THREE };
