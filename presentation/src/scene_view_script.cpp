// The JavaScript of the report's 3D view (docs/report.md). It reads the JSON that
// SceneView3d::html embeds, builds three.js objects and renders on demand (no animation loop, so
// an open report costs no CPU). The outcome is left in #sv3d's data-status ("ok" or
// "error: ...") for tests in a headless browser and shown to the reader on failure.
#include "skelgrasp/presentation/scene_view.h"

namespace skelgrasp::presentation::detail {

const char* const kSceneViewScript = R"js(
(function () {
  const root = document.getElementById('sv3d');
  const message = document.getElementById('sv3d-message');
  function fail(text) {
    root.dataset.status = 'error: ' + text;
    message.textContent = '3D view unavailable: ' + text;
  }
  window.addEventListener('error', function (e) { fail(e.message); });
  try {
    if (typeof THREE === 'undefined') throw new Error('three.js did not load');
    const data = JSON.parse(document.getElementById('sv3d-data').textContent);
    const canvas = document.getElementById('sv3d-canvas');
    const renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true});
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0xf4f4f6);
    const scene = new THREE.Scene();
    const camera = new THREE.PerspectiveCamera(40, 1, 0.001, 100);
    camera.up.set(0, 0, 1);  // scans and meshes are z-up
    scene.add(new THREE.AmbientLight(0xffffff, 0.55));
    const light = new THREE.DirectionalLight(0xffffff, 0.6);
    camera.add(light);
    scene.add(camera);

    function bytes(b64) {
      const s = atob(b64);
      const a = new Uint8Array(s.length);
      for (let i = 0; i < s.length; ++i) a[i] = s.charCodeAt(i);
      return a;
    }
    function positions(p) {
      const q = new Uint16Array(bytes(p.q).buffer);
      const out = new Float32Array(q.length);
      for (let i = 0; i < q.length; ++i) out[i] = p.min[i % 3] + q[i] * p.scale[i % 3];
      return out;
    }
    function colour(c) { return new THREE.Color(c[0] / 255, c[1] / 255, c[2] / 255); }
    function geometry(item) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(positions(item.pos), 3));
      if (item.colors) {
        const c = bytes(item.colors), f = new Float32Array(c.length);
        for (let i = 0; i < c.length; ++i) f[i] = c[i] / 255;
        g.setAttribute('color', new THREE.BufferAttribute(f, 3));
      }
      if (item.index) {
        g.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes(item.index).buffer), 1));
        g.computeVertexNormals();
      }
      return g;
    }
    function meshObject(item) {
      const material = new THREE.MeshLambertMaterial({
        color: item.colors ? 0xffffff : colour(item.colour), vertexColors: !!item.colors,
        side: THREE.DoubleSide, transparent: item.opacity < 1, opacity: item.opacity || 1});
      return new THREE.Mesh(geometry(item), material);
    }

    const layers = {};
    const bounds = new THREE.Box3();
    const focus = new THREE.Box3();  // meshes (the objects): what the camera frames first
    for (const item of data.items) {
      let object;
      if (item.kind === 'mesh') {
        object = meshObject(item);
      } else if (item.kind === 'points') {
        object = new THREE.Points(geometry(item), new THREE.PointsMaterial({
          size: item.size, vertexColors: !!item.colors,
          color: item.colors ? 0xffffff : colour(item.colour)}));
      } else {
        object = new THREE.LineSegments(geometry(item),
                                        new THREE.LineBasicMaterial({color: colour(item.colour)}));
      }
      object.geometry.computeBoundingBox();
      bounds.union(object.geometry.boundingBox);
      if (item.kind === 'mesh') focus.union(object.geometry.boundingBox);
      scene.add(object);
      (layers[item.layer] = layers[item.layer] || []).push(object);
    }

    const partGeometry = data.parts.map(geometry);
    const grasps = data.grasps.map(function (g) {
      const group = new THREE.Group();
      g.parts.forEach(function (placed) {
        const part = data.parts[placed.part];
        const mesh = new THREE.Mesh(partGeometry[placed.part], new THREE.MeshLambertMaterial({
          color: part.colors ? 0xffffff : colour(part.colour), vertexColors: !!part.colors,
          side: THREE.DoubleSide}));
        mesh.matrixAutoUpdate = false;
        mesh.matrix.fromArray(placed.matrix);
        group.add(mesh);
      });
      const ends = [];
      const points = [];
      g.contacts.forEach(function (c) {
        points.push(c[0], c[1], c[2]);
        ends.push(c[0], c[1], c[2], c[0] + 0.02 * c[3], c[1] + 0.02 * c[4], c[2] + 0.02 * c[5]);
      });
      if (points.length) {
        const pg = new THREE.BufferGeometry();
        pg.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
        const dots = new THREE.Points(pg, new THREE.PointsMaterial({color: 0xdc143c, size: 0.006}));
        dots.renderOrder = 1;
        dots.material.depthTest = false;  // contacts stay visible inside the closed hand
        group.add(dots);
        const lg = new THREE.BufferGeometry();
        lg.setAttribute('position', new THREE.Float32BufferAttribute(ends, 3));
        group.add(new THREE.LineSegments(lg, new THREE.LineBasicMaterial({color: 0xdc143c})));
      }
      group.visible = false;
      scene.add(group);
      return group;
    });

    const controls = new THREE.OrbitControls(camera, canvas);
    const framed = focus.isEmpty() ? bounds : focus;
    const sphere = framed.isEmpty() ? new THREE.Sphere(new THREE.Vector3(), 0.1)
                                    : framed.getBoundingSphere(new THREE.Sphere());
    const radius = Math.max(sphere.radius, 0.01);
    controls.target.copy(sphere.center);
    camera.position.copy(sphere.center).add(new THREE.Vector3(1.2, -1.6, 1.1).multiplyScalar(radius * 1.6));
    camera.near = radius / 100;
    camera.far = Math.max(radius, bounds.getBoundingSphere(new THREE.Sphere()).radius) * 100;
    controls.update();  // orients the camera toward the target before the first frame

    function render() {
      const width = canvas.clientWidth, height = canvas.clientHeight;
      if (canvas.width !== width || canvas.height !== height) {
        renderer.setSize(width, height, false);
        camera.aspect = width / Math.max(height, 1);
      }
      camera.updateProjectionMatrix();
      renderer.render(scene, camera);
    }
    controls.addEventListener('change', render);
    window.addEventListener('resize', render);

    const layerBox = document.getElementById('sv3d-layers');
    Object.keys(layers).forEach(function (name) {
      const label = document.createElement('label');
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.checked = true;
      box.addEventListener('change', function () {
        layers[name].forEach(function (o) { o.visible = box.checked; });
        render();
      });
      label.appendChild(box);
      label.appendChild(document.createTextNode(' ' + name + '  '));
      layerBox.appendChild(label);
    });

    const rows = document.querySelectorAll('#sv3d-grasps tr');
    function show(k) {
      grasps.forEach(function (g, i) { g.visible = i === k; });
      rows.forEach(function (r, i) { r.style.background = i === k ? '#ffe9a8' : ''; });
      root.dataset.grasp = String(k);
      render();
    }
    rows.forEach(function (r, i) { r.addEventListener('click', function () { show(i); }); });
    show(grasps.length ? 0 : -1);
    root.dataset.status = 'ok';
  } catch (e) {
    fail(e.message);
  }
})();
)js";

}  // namespace skelgrasp::presentation::detail
