// The report's 3D view (section #view3d): three.js, inlined before this script as the global
// THREE, draws what geomcheck/report/html_scene.py put in #v3d-data: the links at their world
// poses, visual meshes grey, collision elements translucent in the colour of their worst
// finding, suggested primitives dashed, sweeps' closest poses as ghosts. It decides nothing
// about the robot. Nothing is fetched: the meshes are base64 in the page. Without WebGL the
// section keeps its pointer to the orthographic views. The state it shows is mirrored on the
// section's element (data-ready, data-focus, data-shown) for people and tests to read.
(function () {
  "use strict";
  const root = document.querySelector("[data-v3d]");
  const source = document.getElementById("v3d-data");
  if (!root || !source || typeof THREE === "undefined") return;
  root.dataset.startMs = String(Math.round(performance.now()));
  // the rest of the page is shown first: creating the WebGL context and compiling the shaders
  // take a while where WebGL runs in software
  requestAnimationFrame(function () {
    setTimeout(start, 0);
  });

  function start() {

    const COLOURS = { visual: 0xa8b0bc, error: 0xdc2626, warning: 0xf59e0b, info: 0x2563eb, none: 0x2563eb };
    const SUGGESTED = 0x059669;
    const POSE = 0x7c3aed;
    const CONTACT = 0xb91c1c;
    const stage = root.querySelector(".v3d-stage");
    const side = root.querySelector(".v3d-side");
    const canvas = root.querySelector(".v3d-canvas");
    const focusLine = root.querySelector(".v3d-focus");

    function webgl() {
      try {
        const probe = document.createElement("canvas");
        return Boolean(window.WebGL2RenderingContext && probe.getContext("webgl2"));
      } catch (err) {
        return false;
      }
    }
    if (!webgl()) return; // the fallback text stays

    let renderer;
    try {
      renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
    } catch (err) {
      return;
    }
    const data = JSON.parse(source.textContent);
    root.querySelector(".v3d-fallback").hidden = true;
    stage.hidden = false;
    side.hidden = false;
    root.classList.add("live");

    renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    renderer.setClearColor(0xf8fafc, 1);
    const scene = new THREE.Scene();
    const camera = new THREE.PerspectiveCamera(40, 1, 0.001, 1000);
    camera.up.set(0, 0, 1); // robot descriptions are z-up
    scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8f98, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(0.4, -0.6, 1);
    camera.add(sun);
    scene.add(camera);
    const controls = new THREE.OrbitControls(camera, canvas);
    controls.enableDamping = false;
    controls.screenSpacePanning = true;

    // ---- geometry ----

    function bytes(text) {
      const raw = atob(text);
      const out = new Uint8Array(raw.length);
      for (let i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
      return out.buffer;
    }

    const meshGeometries = data.meshes.map(function (m) {
      const grid = new Uint16Array(bytes(m.positions));
      const positions = new Float32Array(grid.length);
      for (let i = 0; i < grid.length; i += 3) {
        positions[i] = m.origin[0] + m.step * grid[i];
        positions[i + 1] = m.origin[1] + m.step * grid[i + 1];
        positions[i + 2] = m.origin[2] + m.step * grid[i + 2];
      }
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
      const indices = m.index_bytes === 4 ? new Uint32Array(bytes(m.indices)) : new Uint16Array(bytes(m.indices));
      geometry.setIndex(new THREE.BufferAttribute(indices, 1));
      return geometry;
    });

    function shapeGeometry(g) {
      if (!g) return null;
      if (g.type === "box") return new THREE.BoxGeometry(g.size[0], g.size[1], g.size[2]);
      if (g.type === "sphere") return new THREE.SphereGeometry(g.radius, 32, 16);
      if (g.type === "cylinder") return new THREE.CylinderGeometry(g.radius, g.radius, g.length, 40).rotateX(Math.PI / 2);
      if (g.type === "mesh" && g.mesh !== null && g.mesh !== undefined) return meshGeometries[g.mesh] || null;
      return null;
    }

    // URDF <origin xyz rpy>: R = Rz(yaw) Ry(pitch) Rx(roll)
    function poseMatrix(p) {
      const xyz = (p && p.xyz) || [0, 0, 0];
      const rpy = (p && p.rpy) || [0, 0, 0];
      const cr = Math.cos(rpy[0]), sr = Math.sin(rpy[0]);
      const cp = Math.cos(rpy[1]), sp = Math.sin(rpy[1]);
      const cy = Math.cos(rpy[2]), sy = Math.sin(rpy[2]);
      return new THREE.Matrix4().set(
        cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, xyz[0],
        sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr, xyz[1],
        -sp, cp * sr, cp * cr, xyz[2],
        0, 0, 0, 1
      );
    }

    function placed(object, matrix) {
      object.matrixAutoUpdate = false;
      object.matrix.copy(matrix);
      return object;
    }

    const materials = {
      visual: new THREE.MeshLambertMaterial({ color: COLOURS.visual, flatShading: true }),
      pose: new THREE.MeshLambertMaterial({ color: POSE, transparent: true, opacity: 0.35, depthWrite: false }),
    };
    function collisionMaterial(severity, strong) {
      return new THREE.MeshLambertMaterial({
        color: COLOURS[severity || "none"],
        transparent: true,
        opacity: strong ? 0.55 : 0.3,
        depthWrite: false,
        side: THREE.DoubleSide,
        // drawn a hair in front: a box flush with the mesh's face shows its colour, not stripes
        polygonOffset: true,
        polygonOffsetFactor: -1,
        polygonOffsetUnits: -4,
      });
    }
    function edges(geometry, colour, dashed, size) {
      const lines = new THREE.EdgesGeometry(geometry, 20);
      const material = dashed
        ? new THREE.LineDashedMaterial({ color: colour, dashSize: size / 14, gapSize: size / 22 })
        : new THREE.LineBasicMaterial({ color: colour });
      const segments = new THREE.LineSegments(lines, material);
      if (dashed) segments.computeLineDistances();
      return segments;
    }
    function sizeOf(geometry) {
      geometry.computeBoundingSphere();
      return Math.max(2 * geometry.boundingSphere.radius, 1e-3);
    }

    // ---- the robot ----

    const contactLinks = new Set();
    data.contacts.forEach(function (pair) {
      pair.forEach(function (name) { contactLinks.add(name); });
    });
    const links = new Map(); // name -> {group, parts: [{kind, key, object}]}
    data.links.forEach(function (link) {
      const group = placed(new THREE.Group(), poseMatrix(link.pose));
      group.name = link.link;
      const parts = [];
      function add(kind, key, object) {
        object.userData = { kind: kind, key: link.link + "/" + key };
        group.add(object);
        parts.push(object);
      }
      link.visuals.forEach(function (e) {
        const geometry = shapeGeometry(e.geometry);
        if (geometry) add("visual", e.label, placed(new THREE.Mesh(geometry, materials.visual), poseMatrix(e.origin)));
      });
      link.collisions.forEach(function (e) {
        const geometry = shapeGeometry(e.geometry);
        if (!geometry) return;
        const shape = new THREE.Group();
        shape.add(new THREE.Mesh(geometry, collisionMaterial(e.severity, contactLinks.has(link.link))));
        if (e.geometry.type !== "mesh") {
          shape.add(edges(geometry, contactLinks.has(link.link) ? CONTACT : COLOURS[e.severity || "none"], false, 1));
        }
        add("collision", e.label, placed(shape, poseMatrix(e.origin)));
      });
      link.suggested.forEach(function (s) {
        const geometry = shapeGeometry(s.geometry);
        if (geometry) {
          add("suggested", "suggested:" + s.for, placed(edges(geometry, SUGGESTED, true, sizeOf(geometry)), poseMatrix(s.origin)));
        }
      });
      scene.add(group);
      group.updateMatrixWorld(true);
      links.set(link.link, { group: group, parts: parts, pose: link.pose });
    });

    // ghosts of the links a sweep or a finding turns, at the angle it speaks of
    const ghosts = new THREE.Group();
    scene.add(ghosts);
    function ghost(poses, tag) {
      Object.keys(poses).forEach(function (name) {
        const link = links.get(name);
        if (!link) return;
        const group = placed(new THREE.Group(), poseMatrix(poses[name]));
        group.userData = { tag: tag };
        link.parts.forEach(function (part) {
          if (part.userData.kind === "suggested") return;
          const source = part.userData.kind === "collision" ? part.children[0] : part;
          const copy = placed(new THREE.Mesh(source.geometry, materials.pose), part.matrix);
          copy.userData = { kind: "pose", key: name + "/pose:" + tag + "/" + part.userData.key.split("/").pop() };
          group.add(copy);
        });
        ghosts.add(group);
      });
    }
    data.sweeps.forEach(function (s, i) { ghost(s.poses, "sweep" + i); });

    // ---- what is shown ----

    const shown = { visual: true, collision: true, suggested: true, poses: false };
    let focus = null; // {links: Set, keys: Set|null, ghost: tag|null, label}

    function visible(object) {
      const kind = object.userData.kind;
      const name = object.userData.key.split("/")[0];
      if (kind === "pose") {
        const tag = object.parent.userData.tag;
        if (focus) return tag === focus.ghost && focus.links.has(name);
        return shown.poses && tag.startsWith("sweep");
      }
      if (!shown[kind]) return false;
      if (!focus) return true;
      if (!focus.links.has(name)) return false;
      if (!focus.keys || kind === "visual") return true;
      return focus.keys.has(object.userData.key);
    }

    function apply() {
      const keys = [];
      links.forEach(function (link) {
        link.parts.forEach(function (part) {
          part.visible = visible(part);
          if (part.visible) keys.push(part.userData.key);
        });
      });
      ghosts.children.forEach(function (group) {
        let any = false;
        group.children.forEach(function (part) {
          part.visible = visible(part);
          any = any || part.visible;
          if (part.visible) keys.push(part.userData.key);
        });
        group.visible = any;
      });
      root.dataset.shown = JSON.stringify(keys);
      root.dataset.focus = focus ? focus.id : "";
      focusLine.textContent = focus ? focus.label : "";
      render();
    }

    function frame() {
      scene.updateMatrixWorld(true);
      const box = new THREE.Box3();
      links.forEach(function (link) {
        link.parts.forEach(function (part) { if (part.visible) box.expandByObject(part); });
      });
      ghosts.children.forEach(function (group) { if (group.visible) box.expandByObject(group); });
      if (box.isEmpty()) links.forEach(function (link) { box.expandByObject(link.group); });
      if (box.isEmpty()) return;
      const sphere = box.getBoundingSphere(new THREE.Sphere());
      const radius = Math.max(sphere.radius, 0.02);
      // the narrower of the two fields of view decides (a phone's canvas is taller than wide)
      const half = Math.min((camera.fov * Math.PI) / 360, Math.atan(Math.tan((camera.fov * Math.PI) / 360) * camera.aspect));
      const distance = radius / Math.sin(half);
      const direction = new THREE.Vector3(1, -1.25, 0.8).normalize();
      camera.position.copy(sphere.center).addScaledVector(direction, distance);
      camera.near = distance / 100;
      camera.far = distance * 100;
      camera.updateProjectionMatrix();
      controls.target.copy(sphere.center);
      controls.update();
    }

    function focusOn(item, id, label, keys, ghostTag) {
      focus = { id: id, links: new Set(item.links.concat(Object.keys(item.poses || {}))), keys: keys, ghost: ghostTag, label: label };
      root.querySelectorAll(".v3d-item").forEach(function (b) { b.setAttribute("aria-pressed", String(b.dataset.key === id)); });
      apply();
      frame();
      render();
    }

    root.querySelectorAll("[data-finding]").forEach(function (button) {
      const index = Number(button.dataset.finding);
      const f = data.findings[index];
      button.dataset.key = f.id;
      if (f.poses && Object.keys(f.poses).length) ghost(f.poses, f.id);
      button.addEventListener("click", function () {
        let keys = null;
        if (f.elements.length) {
          keys = new Set();
          f.elements.forEach(function (e) {
            keys.add(e[0] + "/" + e[1]);
            keys.add(e[0] + "/suggested:" + e[1]);
          });
        }
        const hasPose = f.poses && Object.keys(f.poses).length;
        focusOn(f, f.id, f.code + " " + f.subject + (f.about ? " " + f.about : "") + ": " + f.message, keys, hasPose ? f.id : null);
      });
    });
    root.querySelectorAll("[data-sweep]").forEach(function (button) {
      const index = Number(button.dataset.sweep);
      const s = data.sweeps[index];
      button.dataset.key = "sweep" + index;
      button.addEventListener("click", function () {
        focusOn({ links: s.pair, poses: s.poses }, "sweep" + index, s.joint + ": " + s.label, null, "sweep" + index);
      });
    });
    root.querySelectorAll("[data-show]").forEach(function (box) {
      box.addEventListener("change", function () {
        shown[box.dataset.show] = box.checked;
        apply();
      });
    });
    root.querySelector("[data-v3d-all]").addEventListener("click", function () {
      focus = null;
      root.querySelectorAll(".v3d-item").forEach(function (b) { b.setAttribute("aria-pressed", "false"); });
      apply();
      frame();
      render();
    });

    // ---- joint sliders: frame = parent @ origin @ motion(value), as the scene section says ----

    const values = {};
    data.variables.forEach(function (v) { values[v.joint] = v.value; });
    const origins = data.frames.map(function (f) { return poseMatrix(f.origin); });
    function pose() {
      const world = new Map([[data.root, new THREE.Matrix4()]]);
      const motion = new THREE.Matrix4();
      const axis = new THREE.Vector3();
      data.frames.forEach(function (f, i) {
        const parent = world.get(f.parent);
        if (!parent) return;
        const m = parent.clone().multiply(origins[i]);
        if (f.motion !== "fixed" && f.variable !== null) {
          const value = f.multiplier * (values[f.variable] || 0) + f.offset;
          axis.set(f.axis[0], f.axis[1], f.axis[2]);
          if (f.motion === "translation") motion.makeTranslation(axis.x * value, axis.y * value, axis.z * value);
          else motion.makeRotationAxis(axis, value);
          m.multiply(motion);
        }
        world.set(f.frame, m);
      });
      links.forEach(function (link, name) {
        link.group.matrix.copy(world.get(name) || poseMatrix(link.pose));
      });
      // the sweeps' and findings' poses are about the default pose: hidden away from it
      ghosts.visible = data.variables.every(function (v) { return values[v.joint] === v.value; });
      render();
    }
    const sliders = root.querySelector(".v3d-sliders");
    if (sliders) {
      data.variables.forEach(function (v) {
        const label = document.createElement("label");
        const name = document.createElement("span");
        name.className = "mono";
        name.textContent = v.joint;
        const input = document.createElement("input");
        input.type = "range";
        input.min = String(v.lower);
        input.max = String(v.upper);
        input.step = String((v.upper - v.lower) / 400 || 0.001);
        input.value = String(v.value);
        input.dataset.joint = v.joint;
        input.addEventListener("input", function () {
          values[v.joint] = Number(input.value);
          pose();
        });
        label.append(name, input);
        sliders.append(label);
      });
      root.querySelector("[data-v3d-reset]").addEventListener("click", function () {
        data.variables.forEach(function (v) { values[v.joint] = v.value; });
        sliders.querySelectorAll("input").forEach(function (input) { input.value = String(values[input.dataset.joint]); });
        links.forEach(function (link) { link.group.matrix.copy(poseMatrix(link.pose)); });
        ghosts.visible = true;
        render();
      });
    }

    // ---- drawing, on demand ----

    let pending = false;
    function draw() {
      pending = false;
      renderer.render(scene, camera);
      if (!root.dataset.ready) {
        root.dataset.ready = "1";
        root.dataset.firstFrameMs = String(Math.round(performance.now()));
      }
    }
    function render() {
      if (!pending) {
        pending = true;
        requestAnimationFrame(draw);
      }
    }
    function resize() {
      const width = Math.max(stage.clientWidth, 1);
      const height = Math.max(canvas.clientHeight, 1);
      renderer.setSize(width, height, false);
      camera.aspect = width / height;
      camera.updateProjectionMatrix();
      render();
    }
    controls.addEventListener("change", render);
    new ResizeObserver(resize).observe(stage);
    resize();
    apply();
    frame();
    render();
  }
})();
