// The motion viewer's page script (motion_viewer.hpp). It reads the scene from the JSON block
// #rt-viewer-data (float32/uint32/uint8 arrays in base64, computed by retarget) and only places
// meshes: no kinematics here. World: z up, floor z = 0, metres.
(function () {
  'use strict';
  var status = document.getElementById('rt-status');
  function fail(message) { window.rtViewerFail(message); }
  if (typeof THREE === 'undefined') { fail('three.js did not load'); return; }

  var data = JSON.parse(document.getElementById('rt-viewer-data').textContent);
  function bytes(b64) {
    var s = atob(b64), out = new Uint8Array(s.length);
    for (var i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
    return out;
  }
  function f32(b64) { var b = bytes(b64); return new Float32Array(b.buffer, 0, b.length / 4); }
  function u32(b64) { var b = bytes(b64); return new Uint32Array(b.buffer, 0, b.length / 4); }

  var T = data.num_frames, L = data.link_names.length, fps = data.fps;
  var poses = f32(data.link_poses), soles = f32(data.sole_corners_W), com = f32(data.com_W);
  var contact = data.contact ? [bytes(data.contact[0]), bytes(data.contact[1])] : null;
  var comPlan = data.com_planned_W ? f32(data.com_planned_W) : null;
  var copPlan = data.cop_planned_W ? f32(data.cop_planned_W) : null;
  if (poses.length !== T * L * 7) { fail('link_poses has ' + poses.length + ' values, expected ' + T * L * 7); return; }

  // The robot's size at frame 0 scales the camera distance and the labels.
  var zmax = 0, rootX = poses[0], rootY = poses[1];
  for (var k = 0; k < L; ++k) zmax = Math.max(zmax, poses[7 * k + 2]);
  var height = Math.max(0.3, zmax * 1.15);

  // ---- renderer, camera, lights, floor --------------------------------------------------------
  var view = document.getElementById('view');
  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  } catch (e) { fail('WebGL is not available in this browser (' + e.message + ')'); return; }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  view.appendChild(renderer.domElement);
  var scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f2);
  var camera = new THREE.PerspectiveCamera(40, 1, 0.02, 200);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8a80, 0.75));
  var sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(2, -3, 5);
  scene.add(sun);
  var floor = new THREE.Mesh(new THREE.PlaneGeometry(40, 40),
                             new THREE.MeshLambertMaterial({color: 0xe6e6e0}));
  floor.position.z = -0.001;
  scene.add(floor);
  var grid = new THREE.GridHelper(20, 80, 0xb0b0a8, 0xcfcfc8);
  grid.rotation.x = Math.PI / 2;
  scene.add(grid);

  // ---- robot ----------------------------------------------------------------------------------
  var links = [];
  for (var l = 0; l < L; ++l) { var g = new THREE.Group(); g.name = data.link_names[l]; scene.add(g); links.push(g); }
  var footMaterials = [[], []];
  var contactColor = new THREE.Color(0x2e9e4a), swingColor = [null, null];
  data.meshes.forEach(function (m) {
    var geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(f32(m.positions_L), 3));
    geo.setIndex(new THREE.BufferAttribute(u32(m.indices), 1));
    geo.computeVertexNormals();
    var mat = new THREE.MeshPhongMaterial({color: new THREE.Color(m.color[0], m.color[1], m.color[2]),
                                           flatShading: true, side: THREE.DoubleSide, shininess: 20});
    for (var side = 0; side < 2; ++side)
      if (m.link === data.foot_links[side]) { footMaterials[side].push(mat); swingColor[side] = mat.color.clone(); }
    links[m.link].add(new THREE.Mesh(geo, mat));
  });

  // ---- soles, support polygon, COM, ZMP ------------------------------------------------------
  function lineLoop(n, color) {
    var geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * n), 3));
    var line = new THREE.LineLoop(geo, new THREE.LineBasicMaterial({color: color}));
    line.frustumCulled = false;
    scene.add(line);
    return line;
  }
  var soleLines = [lineLoop(4, 0x2e9e4a), lineLoop(4, 0x2e9e4a)];
  var supportGeo = new THREE.BufferGeometry();
  supportGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * 3 * 8), 3));
  var support = new THREE.Mesh(supportGeo, new THREE.MeshBasicMaterial({color: 0x2e9e4a, transparent: true,
                                                                           opacity: 0.28, side: THREE.DoubleSide,
                                                                           depthWrite: false}));
  support.frustumCulled = false;
  scene.add(support);
  function dot(radius, color) {
    // Drawn over the robot: the COM is inside the body.
    var m = new THREE.Mesh(new THREE.SphereGeometry(radius, 16, 10),
                           new THREE.MeshBasicMaterial({color: color, depthTest: false}));
    m.renderOrder = 4;
    scene.add(m);
    return m;
  }
  function disc(radius, color) {
    var m = new THREE.Mesh(new THREE.CircleGeometry(radius, 20),
                           new THREE.MeshBasicMaterial({color: color, depthTest: false}));
    m.renderOrder = 4;
    m.position.z = 0.003;
    scene.add(m);
    return m;
  }
  function trace(values, stride, color) {  // a floor path through every frame
    var p = new Float32Array(3 * T);
    for (var f = 0; f < T; ++f) { p[3 * f] = values[stride * f]; p[3 * f + 1] = values[stride * f + 1]; p[3 * f + 2] = 0.002; }
    var geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(p, 3));
    var line = new THREE.Line(geo, new THREE.LineBasicMaterial({color: color, transparent: true, opacity: 0.7}));
    scene.add(line);
    return line;
  }
  var layers = {};
  function layer(name, label, color, objects, on) {
    layers[name] = {objects: objects, on: on};
    var box = document.createElement('label');
    var input = document.createElement('input');
    input.type = 'checkbox';
    input.checked = on;
    input.id = 'layer-' + name;
    input.addEventListener('change', function () { layers[name].on = input.checked; show(frame); });
    box.appendChild(input);
    if (color !== null) {
      var key = document.createElement('span');
      key.className = 'key';
      key.style.background = '#' + new THREE.Color(color).getHexString();
      box.appendChild(key);
    }
    box.appendChild(document.createTextNode(label));
    document.getElementById('layers').appendChild(box);
  }
  var comDot = dot(0.025, 0xe07b00), comFloor = disc(0.018, 0xe07b00);
  layer('com', 'COM (kinematic)', 0xe07b00, [comDot, comFloor], true);
  var comPlanDot = null, comPlanFloor = null, copDisc = null;
  if (comPlan) {
    comPlanDot = dot(0.02, 0x2a62c9);
    comPlanFloor = disc(0.014, 0x2a62c9);
    layer('com_planned', 'COM (planned)', 0x2a62c9, [comPlanDot, comPlanFloor, trace(comPlan, 3, 0x2a62c9)], true);
  }
  if (copPlan) {
    copDisc = disc(0.02, 0xc8102e);
    layer('zmp', 'ZMP (planned)', 0xc8102e, [copDisc, trace(copPlan, 2, 0xc8102e)], true);
  }
  layer('support', 'support polygon', 0x2e9e4a, [support, soleLines[0], soleLines[1]], true);

  // ---- points: the source skeleton, the robot's landmarks ------------------------------------
  function pointSet(set, color, size) {
    var N = set.names.length, p = f32(set.p_W), valid = bytes(set.valid);
    var pointsGeo = new THREE.BufferGeometry();
    pointsGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * N), 3));
    var points = new THREE.Points(pointsGeo, new THREE.PointsMaterial({color: color, size: size, sizeAttenuation: true,
                                                                        depthTest: false}));
    var bonesGeo = new THREE.BufferGeometry();
    bonesGeo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * Math.max(1, set.bones.length)), 3));
    var bones = new THREE.LineSegments(bonesGeo, new THREE.LineBasicMaterial({color: color, depthTest: false}));
    points.renderOrder = bones.renderOrder = 2;
    points.frustumCulled = bones.frustumCulled = false;  // they move: no stale bounding sphere
    scene.add(points);
    scene.add(bones);
    return {N: N, p: p, valid: valid, bones: set.bones, points: points, lines: bones, offset: [0, 0, 0],
            place: function (f) {
              var src = f * N * 3, pos = points.geometry.attributes.position.array, off = this.offset;
              for (var i = 0; i < N; ++i)
                for (var k = 0; k < 3; ++k)
                  // A missing point goes beyond the far plane (NaN would upset three.js).
                  pos[3 * i + k] = valid[f * N + i] ? p[src + 3 * i + k] + off[k] : (k === 2 ? -1000 : 0);
              points.geometry.attributes.position.needsUpdate = true;
              var b = bones.geometry.attributes.position.array;
              for (var j = 0; j < set.bones.length; ++j) {
                var a = set.bones[j][0], z = set.bones[j][1], ok = valid[f * N + a] && valid[f * N + z];
                for (var e = 0; e < 2; ++e)
                  for (var c = 0; c < 3; ++c) b[6 * j + 3 * e + c] = ok ? pos[3 * set.bones[j][e] + c] : (c === 2 ? -1000 : 0);
              }
              bones.geometry.attributes.position.needsUpdate = true;
            }};
  }
  var skeleton = null;
  if (data.skeleton) {
    skeleton = pointSet(data.skeleton, 0x8a2be2, 0.035);
    layer('skeleton', 'human (scaled landmarks)', 0x8a2be2, [skeleton.points, skeleton.lines], true);
    layer('beside', 'human beside the robot', null, [], false);
  }
  var landmarkSet = null;
  if (data.landmarks) {
    landmarkSet = pointSet(data.landmarks, 0x8a2be2, 0.03);
    var labels = [];
    var lp = f32(data.landmarks.p_W);
    data.landmarks.names.forEach(function (name, i) {
      var canvas = document.createElement('canvas');
      canvas.width = 1024; canvas.height = 64;
      var ctx = canvas.getContext('2d');
      ctx.font = 'bold 40px sans-serif';
      ctx.fillStyle = '#5a1d96';
      ctx.fillText(name, 4, 46);
      var sprite = new THREE.Sprite(new THREE.SpriteMaterial({map: new THREE.CanvasTexture(canvas), depthTest: false}));
      sprite.scale.set(0.04 * height * 16, 0.04 * height, 1);  // text height 1/25 of the robot
      sprite.center.set(0, 0.5);
      sprite.position.set(lp[3 * i] + 0.02, lp[3 * i + 1], lp[3 * i + 2]);
      sprite.renderOrder = 3;
      scene.add(sprite);
      labels.push(sprite);
    });
    layer('landmarks', 'landmarks', 0x8a2be2, [landmarkSet.points, landmarkSet.lines].concat(labels), true);
  }

  // ---- per-frame placement --------------------------------------------------------------------
  function inContact(side, f) { return contact ? contact[side][f] === 1 : false; }
  function hull(pts) {  // Andrew's monotone chain, counter-clockwise
    pts.sort(function (a, b) { return a[0] - b[0] || a[1] - b[1]; });
    function cross(o, a, b) { return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]); }
    var lower = [], upper = [];
    pts.forEach(function (p) {
      while (lower.length >= 2 && cross(lower[lower.length - 2], lower[lower.length - 1], p) <= 0) lower.pop();
      lower.push(p);
    });
    for (var i = pts.length - 1; i >= 0; --i) {
      var p = pts[i];
      while (upper.length >= 2 && cross(upper[upper.length - 2], upper[upper.length - 1], p) <= 0) upper.pop();
      upper.push(p);
    }
    return lower.slice(0, -1).concat(upper.slice(0, -1));
  }
  var frame = 0;
  function show(f) {
    frame = f;
    for (var l = 0; l < L; ++l) {
      var o = 7 * (f * L + l);
      links[l].position.set(poses[o], poses[o + 1], poses[o + 2]);
      links[l].quaternion.set(poses[o + 3], poses[o + 4], poses[o + 5], poses[o + 6]);
    }
    var pts = [];
    for (var side = 0; side < 2; ++side) {
      var c = inContact(side, f);
      footMaterials[side].forEach(function (m) { m.color.copy(c ? contactColor : swingColor[side]); });
      var pos = soleLines[side].geometry.attributes.position.array;
      for (var k = 0; k < 4; ++k) {
        var s = 24 * f + 12 * side + 3 * k;
        pos[3 * k] = soles[s]; pos[3 * k + 1] = soles[s + 1]; pos[3 * k + 2] = Math.max(soles[s + 2], 0) + 0.002;
        if (c) pts.push([soles[s], soles[s + 1]]);
      }
      soleLines[side].geometry.attributes.position.needsUpdate = true;
      soleLines[side].material.color.set(c ? 0x2e9e4a : 0x999999);
    }
    var tri = supportGeo.attributes.position.array, h = pts.length >= 3 ? hull(pts) : [], n = 0;
    for (var i = 1; i + 1 < h.length; ++i) {
      [h[0], h[i], h[i + 1]].forEach(function (p) { tri[3 * n] = p[0]; tri[3 * n + 1] = p[1]; tri[3 * n + 2] = 0.001; ++n; });
    }
    supportGeo.setDrawRange(0, n);
    supportGeo.attributes.position.needsUpdate = true;
    comDot.position.set(com[3 * f], com[3 * f + 1], com[3 * f + 2]);
    comFloor.position.set(com[3 * f], com[3 * f + 1], 0.004);
    if (comPlan) {
      comPlanDot.position.set(comPlan[3 * f], comPlan[3 * f + 1], comPlan[3 * f + 2]);
      comPlanFloor.position.set(comPlan[3 * f], comPlan[3 * f + 1], 0.005);
    }
    if (copPlan) copDisc.position.set(copPlan[2 * f], copPlan[2 * f + 1], 0.003);
    if (skeleton) {
      skeleton.offset = layers.beside.on ? [0, 0.9, 0] : [0, 0, 0];
      skeleton.place(f);
    }
    if (landmarkSet) landmarkSet.place(0);
    Object.keys(layers).forEach(function (k) { layers[k].objects.forEach(function (o) { o.visible = layers[k].on; }); });
    if (layers.follow && layers.follow.on) {
      var root = 7 * (f * L);
      var dx = poses[root] - controlsTarget.x, dy = poses[root + 1] - controlsTarget.y;
      controlsTarget.x += dx; controlsTarget.y += dy;
      camera.position.x += dx; camera.position.y += dy;
    }
    if (controls) controls.update(); else camera.lookAt(controlsTarget);
    document.getElementById('scrub').value = f;
    document.getElementById('time').textContent = (f / fps).toFixed(2) + ' / ' + ((T - 1) / fps).toFixed(2) + ' s, frame ' + f;
    drawTimeline();
    renderer.render(scene, camera);
  }

  // ---- camera ---------------------------------------------------------------------------------
  var controlsTarget = new THREE.Vector3(rootX, rootY, 0.5 * height);
  camera.position.set(rootX + 1.5 * height, rootY - 1.25 * height, 0.8 * height);
  var controls = null;
  if (THREE.OrbitControls) {
    controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target = controlsTarget;
    controls.addEventListener('change', function () { renderer.render(scene, camera); });
  }
  if (T > 1) layer('follow', 'camera follows', null, [], true);

  // ---- contact timeline -----------------------------------------------------------------------
  var timeline = document.getElementById('timeline');
  function drawTimeline() {
    var w = timeline.clientWidth || 600, hgt = timeline.clientHeight || 28;
    if (timeline.width !== w) timeline.width = w;
    if (timeline.height !== hgt) timeline.height = hgt;
    var ctx = timeline.getContext('2d');
    ctx.clearRect(0, 0, w, hgt);
    ctx.font = '10px sans-serif';
    var x0 = 42, span = w - x0 - 4;
    for (var side = 0; side < 2; ++side) {
      var y = 2 + side * (hgt / 2);
      ctx.fillStyle = '#555';
      ctx.fillText(side ? 'right' : 'left', 2, y + 10);
      ctx.fillStyle = '#e4e4e4';
      ctx.fillRect(x0, y, span, hgt / 2 - 4);
      if (!contact) continue;
      ctx.fillStyle = '#2e9e4a';
      for (var f = 0; f < T; ++f)
        if (contact[side][f]) ctx.fillRect(x0 + span * f / T, y, Math.max(1, span / T + 0.5), hgt / 2 - 4);
    }
    if (!contact) { ctx.fillStyle = '#777'; ctx.fillText('no contact schedule in this reference', x0 + 6, hgt / 2 + 3); }
    ctx.fillStyle = '#c8102e';
    ctx.fillRect(x0 + span * (frame + 0.5) / T - 1, 0, 2, hgt);
  }
  timeline.addEventListener('click', function (e) {
    var r = timeline.getBoundingClientRect(), x0 = 42, span = r.width - x0 - 4;
    pause();
    show(Math.max(0, Math.min(T - 1, Math.floor((e.clientX - r.left - x0) / span * T))));
  });

  // ---- playback -------------------------------------------------------------------------------
  var playing = T > 1, clock = 0, last = null;
  var playButton = document.getElementById('play'), scrub = document.getElementById('scrub');
  scrub.max = T - 1;
  playButton.textContent = playing ? 'pause' : 'play';
  playButton.disabled = T === 1;
  scrub.disabled = T === 1;
  function pause() { playing = false; playButton.textContent = 'play'; }
  playButton.addEventListener('click', function () {
    playing = !playing;
    playButton.textContent = playing ? 'pause' : 'play';
    clock = frame / fps;
    last = null;
  });
  scrub.addEventListener('input', function () { pause(); show(parseInt(scrub.value, 10)); });
  // Keys: space plays / pauses, the arrows step one frame (with shift: one second).
  window.addEventListener('keydown', function (e) {
    if (T === 1 || e.target.tagName === 'SELECT') return;
    if (e.key === ' ') { playButton.click(); e.preventDefault(); return; }
    var step = e.key === 'ArrowRight' ? 1 : e.key === 'ArrowLeft' ? -1 : 0;
    if (!step) return;
    if (e.shiftKey) step *= Math.max(1, Math.round(fps));
    pause();
    show(Math.max(0, Math.min(T - 1, frame + step)));
    e.preventDefault();
  });
  function resize() {
    var w = view.clientWidth || 800, hh = view.clientHeight || 500;
    renderer.setSize(w, hh);
    camera.aspect = w / hh;
    camera.updateProjectionMatrix();
    show(frame);
  }
  window.addEventListener('resize', resize);
  function tick(now) {
    if (playing) {
      if (last !== null) clock += (now - last) / 1000 * parseFloat(document.getElementById('speed').value);
      var duration = T / fps;
      clock = clock % duration;
      var f = Math.min(T - 1, Math.floor(clock * fps));
      if (f !== frame) show(f);
    }
    last = playing ? now : null;
    requestAnimationFrame(tick);
  }

  // ---- info -----------------------------------------------------------------------------------
  var info = document.getElementById('info');
  var tris = data.meshes.reduce(function (a, m) { return a + m.num_triangles; }, 0);
  var head = document.createElement('h1');
  head.textContent = data.title;
  info.appendChild(head);
  var line = document.createElement('div');
  line.textContent = data.robot + ' \u00b7 ' + (data.mode === 'robot' ? 'standing pose' :
                     T + ' frames at ' + fps + ' Hz (' + ((T - 1) / fps).toFixed(2) + ' s)') +
                     ' \u00b7 ' + data.mesh_source + ' meshes, ' + tris + ' triangles \u00b7 feet green in contact';
  info.appendChild(line);
  data.notes.forEach(function (n) {
    var d = document.createElement('div'); d.className = 'notes'; d.textContent = n; info.appendChild(d);
  });

  resize();
  show(0);
  if (status.getAttribute('data-status') !== 'error') {
    status.setAttribute('data-status', 'ok');
    status.setAttribute('data-frames', String(T));
    status.setAttribute('data-meshes', String(data.meshes.length));
    status.textContent = 'three.js r' + THREE.REVISION;
  }
  requestAnimationFrame(tick);
})();
