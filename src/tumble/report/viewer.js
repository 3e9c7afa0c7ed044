(function () {
  const D = JSON.parse(document.getElementById('tumble-data').textContent);
  const gd = document.getElementById('plot');
  const poinsot = document.getElementById('poinsot');
  const P = D.poinsot;
  const slider = document.getElementById('slider');
  const play = document.getElementById('play');
  const clock = document.getElementById('time');
  const n = D.t.length;
  const state = { frame: 0, playing: false, timer: null };
  window.tumbleViewer = state;

  function rotate(q, v) {
    const w = q[0], x = q[1], y = q[2], z = q[3];
    // v + 2w (u × v) + 2 u × (u × v), u = (x, y, z): the rotation of v by q.
    const tx = 2 * (y * v[2] - z * v[1]);
    const ty = 2 * (z * v[0] - x * v[2]);
    const tz = 2 * (x * v[1] - y * v[0]);
    return [
      v[0] + w * tx + (y * tz - z * ty),
      v[1] + w * ty + (z * tx - x * tz),
      v[2] + w * tz + (x * ty - y * tx),
    ];
  }
  function segment(a, b) { return [[a[0], b[0]], [a[1], b[1]], [a[2], b[2]]]; }

  function draw(i) {
    const q = D.q[i];
    const count = D.vertices.length;
    const mx = new Array(count), my = new Array(count), mz = new Array(count);
    for (let k = 0; k < count; k++) {
      const p = rotate(q, D.vertices[k]);
      mx[k] = p[0]; my[k] = p[1]; mz[k] = p[2];
    }
    const c = rotate(q, D.centre);
    const xs = [mx], ys = [my], zs = [mz];
    for (let k = 0; k < 3; k++) {
      const s = segment(c, rotate(q, D.axis_ends[k]));
      xs.push(s[0]); ys.push(s[1]); zs.push(s[2]);
    }
    for (const v of [D.omega[i], D.momentum[i]]) {
      const s = segment([0, 0, 0], v);
      xs.push(s[0]); ys.push(s[1]); zs.push(s[2]);
    }
    const trail = D.omega.slice(0, i + 1);
    xs.push(trail.map(p => p[0])); ys.push(trail.map(p => p[1])); zs.push(trail.map(p => p[2]));
    const traces = [0, 1, 2, 3, 4, 5, 6];
    D.rotors.forEach(function (r, k) {
      // Turned about its axis by its spin angle, about its centre, then with the body.
      const half = 0.5 * r.angles[i], s = Math.sin(half);
      const spin = [Math.cos(half), s * r.axis[0], s * r.axis[1], s * r.axis[2]];
      const rx = [], ry = [], rz = [];
      const c = r.position;
      for (const v of r.vertices) {
        const local = rotate(spin, [v[0] - c[0], v[1] - c[1], v[2] - c[2]]);
        const p = rotate(q, [local[0] + c[0], local[1] + c[1], local[2] + c[2]]);
        rx.push(p[0]); ry.push(p[1]); rz.push(p[2]);
      }
      xs.push(rx); ys.push(ry); zs.push(rz);
      traces.push(8 + k);
    });
    Plotly.restyle(gd, { x: xs, y: ys, z: zs }, traces);
    if (P) {
      // The ellipsoid and the polhode turn with the body; the herpolhode grows on the plane.
      const ex = [], ey = [], ez = [];
      for (const v of P.ellipsoid) {
        const p = rotate(q, v);
        ex.push(p[0]); ey.push(p[1]); ez.push(p[2]);
      }
      const pol = P.polhode.map(v => rotate(q, v));
      const her = P.herpolhode.slice(0, i + 1);
      const tip = P.herpolhode[i];
      Plotly.restyle(poinsot, {
        x: [ex, pol.map(p => p[0]), her.map(p => p[0]), [0, tip[0]], [tip[0]]],
        y: [ey, pol.map(p => p[1]), her.map(p => p[1]), [0, tip[1]], [tip[1]]],
        z: [ez, pol.map(p => p[2]), her.map(p => p[2]), [0, tip[2]], [tip[2]]],
      }, [0, 2, 3, 4, 5]);
    }
    state.frame = i;
    slider.value = i;
    clock.textContent = 't = ' + D.t[i].toFixed(3) + ' s  (' + (i + 1) + ' / ' + n + ')';
  }

  function stop() {
    state.playing = false;
    if (state.timer !== null) { clearInterval(state.timer); state.timer = null; }
    play.textContent = 'Play';
  }
  function start() {
    if (state.frame >= n - 1) { draw(0); }
    state.playing = true;
    play.textContent = 'Pause';
    state.timer = setInterval(function () {
      if (state.frame >= n - 1) { stop(); return; }
      draw(state.frame + 1);
    }, 1000 / 30);
  }
  play.addEventListener('click', function () { state.playing ? stop() : start(); });
  slider.addEventListener('input', function () { stop(); draw(parseInt(slider.value, 10)); });

  const figure = JSON.parse(document.getElementById('tumble-figure').textContent);
  const config = { responsive: true, displaylogo: false };
  const shown = [Plotly.newPlot(gd, figure.data, figure.layout, config)];
  if (P) {
    const second = JSON.parse(document.getElementById('tumble-poinsot').textContent);
    shown.push(Plotly.newPlot(poinsot, second.data, second.layout, config));
  }
  Promise.all(shown).then(function () {
    draw(0);
    state.ready = true;
  });
})();
