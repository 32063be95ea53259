// The page of `vibroatlas explore`: a thin client of the JSON API
// (docs/explore.md). Every colour, legend, label and figure comes from the
// server; this file only lays cells out on a canvas and asks for more.
'use strict';

const $ = (id) => document.getElementById(id);
const canvas = $('map');
const ctx = canvas.getContext('2d');
// Margins of the plot inside the canvas (axes and their labels), px.
const M = { left: 72, right: 14, top: 14, bottom: 52 };

const S = {
  id: 0, info: null, view: null, mass: null,
  image: null, k: 1,           // the cells painted at k x k pixels each
  coarse: null,                // the hysteresis view at a pixel per cell (up colours), for small cells
  box: null,                   // the visible region in cell indices: cell i spans [i - 0.5, i + 0.5]
  curves: [], hovered: null, drag: null, job: null,
};

async function getJSON(url, options) {
  const r = await fetch(url, options);
  const body = await r.json().catch(() => ({ error: r.statusText }));
  if (!r.ok) throw new Error(body.error || r.statusText);
  return body;
}

function say(text) { $('message').textContent = text || ''; }

// An element with its text (never markup: every name and number reaches the
// page as text, whatever a file or scene holds), its attributes and children.
function el(tag, text, attrs, children) {
  const e = document.createElement(tag);
  if (text !== undefined && text !== null) e.textContent = text;
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (children) e.append(...children);
  return e;
}

// Parameter value of a (fractional) index of axis a, and back.
function value(a, f) { return a.count > 1 ? a.start + (f * (a.stop - a.start)) / (a.count - 1) : a.start; }
function index(a, v) { return a.count > 1 ? ((v - a.start) * (a.count - 1)) / (a.stop - a.start) : 0; }
function short(v) { return String(+v.toPrecision(6)); }

function whole() {
  const { x, y } = S.info;
  return { x0: -0.5, x1: x.count - 0.5, y0: -0.5, y1: y.count - 0.5 };
}

// The view kept in the address: atlas, view, mass, and the visible box in parameter values.
function fromAddress() {
  const p = new URLSearchParams(location.search);
  return { atlas: +(p.get('atlas') || 0), view: p.get('view'), mass: p.get('mass'), box: p.get('box'), zoom: p.get('zoom') };
}

function toAddress(push) {
  const p = new URLSearchParams();
  p.set('atlas', S.id);
  p.set('view', S.view);
  p.set('mass', S.mass);
  const b = S.box, { x, y } = S.info;
  p.set('box', [value(x, b.x0), value(x, b.x1), value(y, b.y0), value(y, b.y1)].map(short).join(','));
  // The zooms from the file to this atlas: a colleague's page computes them again.
  if (S.info.boxes.length) p.set('zoom', S.info.boxes.join(' | '));
  const url = '?' + p.toString();
  if (push) history.pushState(null, '', url); else history.replaceState(null, '', url);
}

function fill(select, names, chosen) {
  select.replaceChildren();
  for (const n of names) {
    const o = document.createElement('option');
    o.value = o.textContent = n;
    select.appendChild(o);
  }
  select.value = names.includes(chosen) ? chosen : names[0];
  return select.value;
}

// The atlas of an address whose zooms this server may not have computed
// (another session's link): the chain of boxes from the file, computed again.
async function resolve(at) {
  if (!at.zoom) return at.atlas;
  const known = await getJSON(`/api/atlas?atlas=${at.atlas}`).catch(() => null);
  if (known && known.boxes.join(' | ') === at.zoom) return at.atlas;
  let atlas = 0;
  $('zoom-dialog').hidden = false;
  for (const box of at.zoom.split(' | ')) {
    // `X Y`, or `X Y at NAME=VALUE,…` for a slice at another parameter value.
    const [x, y, , set = ''] = box.trim().split(' ');
    $('zoom-x').value = x;
    $('zoom-y').value = y;
    $('zoom-set').value = set;
    atlas = await zoomJob(atlas, x, y, set);
  }
  return atlas;
}

async function load(at, push) {
  say('');
  at = { ...at, atlas: await resolve(at) };
  S.info = await getJSON(`/api/atlas?atlas=${at.atlas}`);
  S.id = at.atlas;
  S.view = fill($('view'), S.info.views, at.view);
  S.mass = fill($('mass'), S.info.masses, at.mass);
  S.box = whole();
  if (at.box) {
    const v = at.box.split(',').map(Number);
    if (v.length === 4 && v.every(Number.isFinite)) {
      const { x, y } = S.info;
      S.box = { x0: index(x, v[0]), x1: index(x, v[1]), y0: index(y, v[2]), y1: index(y, v[3]) };
    }
  }
  const i = S.info;
  const parent = i.parent ? ` — a box (${i.parent.box}) of atlas ${i.parent.id}` : '';
  $('title').textContent = `${i.scene}: ${i.file}, ${i.x.count} × ${i.y.count} cells${parent}`;
  $('cell').hidden = true;
  S.curves = [];
  await layer();
  toAddress(push);
}

function query() {
  return `atlas=${S.id}&view=${encodeURIComponent(S.view)}&mass=${encodeURIComponent(S.mass)}`;
}

// The view's colours, painted once into an image of the cells.
async function layer() {
  const curves = $('curves').checked ? '&curves=1' : '';
  const [bytes, key] = await Promise.all([
    fetch('/api/map?' + query()).then((r) => (r.ok ? r.arrayBuffer() : r.json().then((e) => Promise.reject(new Error(e.error))))),
    getJSON('/api/legend?' + query() + curves),
  ]);
  S.curves = $('curves').checked ? (await getJSON(`/api/curves?atlas=${S.id}`)).curves : [];
  const { x, y } = S.info, nx = x.count, ny = y.count;
  const split = S.view === 'hysteresis' && nx * ny * 9 <= 12e6;
  const rgb = new Uint8Array(bytes);
  // Each cell in k × k pixels: the upper-left triangle (the rising diagonal
  // included) in the first colour, the rest in the second (k = 1: the first).
  const paint = (k) => {
    const image = new ImageData(nx * k, ny * k);
    const px = new Uint32Array(image.data.buffer);
    const n = nx * ny;
    for (let iy = 0; iy < ny; iy++) {
      const row = ny - 1 - iy;
      for (let ix = 0; ix < nx; ix++) {
        const c = 3 * (iy * nx + ix), d = c + 3 * n;
        const above = 0xff000000 | (rgb[c + 2] << 16) | (rgb[c + 1] << 8) | rgb[c];
        const below = 0xff000000 | (rgb[d + 2] << 16) | (rgb[d + 1] << 8) | rgb[d];
        for (let sy = 0; sy < k; sy++) {
          for (let sx = 0; sx < k; sx++) {
            px[(row * k + sy) * nx * k + ix * k + sx] = sx + sy <= k - 1 ? above : below;
          }
        }
      }
    }
    const off = document.createElement('canvas');
    off.width = nx * k;
    off.height = ny * k;
    off.getContext('2d').putImageData(image, 0, 0);
    return off;
  };
  S.image = paint(split ? 3 : 1);
  S.k = split ? 3 : 1;
  // Split cells below SPLIT_MIN_PX on screen would read as a woven
  // staircase: there each cell shows its up colour, and the page says so.
  S.coarse = split ? paint(1) : null;
  legend(key);
  draw();
  links();
}

function swatch(row) {
  const s = document.createElement('span');
  s.className = 'swatch';
  const c = row.colours.map((v) => `rgb(${v[0]},${v[1]},${v[2]})`);
  if (row.swatch === 'fill') s.style.background = c[0];
  else if (row.swatch === 'split') s.style.background = `linear-gradient(to bottom right, ${c[0]} 50%, ${c[1]} 50%)`;
  else if (row.swatch === 'hatch') s.style.background = `repeating-linear-gradient(45deg, ${c[0]} 0 2px, #fff 2px 5px)`;
  else if (row.swatch === 'line') { s.style.border = 'none'; s.style.borderTop = `3px solid ${c[0]}`; s.style.height = '0'; }
  else { s.style.borderRadius = '50%'; s.style.borderColor = c[0]; if (row.swatch === 'dot') s.style.background = c[0]; }
  return s;
}

function legend(key) {
  const box = $('legend');
  box.replaceChildren();
  if (key.scale) {
    const t = document.createElement('div');
    t.className = 'heading';
    t.textContent = key.scale.title;
    const bar = document.createElement('div');
    bar.className = 'bar';
    bar.style.background = `linear-gradient(to right, ${key.scale.colours.map((v) => `rgb(${v})`).join(',')})`;
    const ends = document.createElement('div');
    ends.className = 'row';
    const gap = el('span');
    gap.style.flex = '1';
    ends.append(el('span', short(key.scale.lo)), gap, el('span', short(key.scale.hi)));
    box.append(t, bar, ends);
  }
  for (const row of key.legend) {
    const d = document.createElement('div');
    if (row.swatch === 'heading') {
      d.className = 'heading';
      d.textContent = row.text;
    } else {
      d.className = 'row';
      const text = document.createElement('span');
      text.textContent = row.text;
      d.append(swatch(row), text);
    }
    box.appendChild(d);
  }
}

function plotSize() {
  return { w: canvas.width - M.left - M.right, h: canvas.height - M.top - M.bottom };
}

// Canvas pixel of a (fractional) cell index, and back.
function toCanvas(fx, fy) {
  const b = S.box, { w, h } = plotSize();
  return [M.left + ((fx - b.x0) / (b.x1 - b.x0)) * w, M.top + ((b.y1 - fy) / (b.y1 - b.y0)) * h];
}
function toCell(cx, cy) {
  const b = S.box, { w, h } = plotSize();
  return [b.x0 + ((cx - M.left) / w) * (b.x1 - b.x0), b.y1 - ((cy - M.top) / h) * (b.y1 - b.y0)];
}

function ticks(lo, hi) {
  const span = hi - lo, raw = span / 6, mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => span / s <= 7);
  const out = [];
  // A tick that sums to a rounding residue of zero (-2.8e-17) is zero.
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-12 * span; v += step) out.push(Math.abs(v) < 1e-9 * step ? 0 : +v.toPrecision(12));
  return out;
}

// Smallest cell, in screen pixels, drawn split along its diagonal.
const SPLIT_MIN_PX = 6;

function draw() {
  const b = S.box, { w, h } = plotSize(), ny = S.info.y.count;
  const cellPx = Math.min(w / (b.x1 - b.x0), h / (b.y1 - b.y0));
  const coarse = S.coarse !== null && cellPx < SPLIT_MIN_PX;
  const [image, k] = coarse ? [S.coarse, 1] : [S.image, S.k];
  $('split-note').hidden = !coarse;
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(image, (b.x0 + 0.5) * k, (ny - 0.5 - b.y1) * k, (b.x1 - b.x0) * k, (b.y1 - b.y0) * k, M.left, M.top, w, h);
  ctx.strokeStyle = '#333';
  ctx.strokeRect(M.left, M.top, w, h);
  // Axes in parameter values, with their symbols.
  const { x, y } = S.info;
  ctx.fillStyle = '#222';
  ctx.font = '12px "DejaVu Sans", sans-serif';
  ctx.textAlign = 'center';
  for (const v of ticks(value(x, b.x0), value(x, b.x1))) {
    const [cx] = toCanvas(index(x, v), b.y0);
    ctx.fillRect(cx, M.top + h, 1, 5);
    ctx.fillText(short(v), cx, M.top + h + 18);
  }
  drawRuns(ctx, x.symbol_runs, M.left + w / 2, M.top + h + 40);
  ctx.textAlign = 'right';
  for (const v of ticks(value(y, b.y0), value(y, b.y1))) {
    const [, cy] = toCanvas(b.x0, index(y, v));
    ctx.fillRect(M.left - 5, cy, 5, 1);
    ctx.fillText(short(v), M.left - 8, cy + 4);
  }
  ctx.save();
  ctx.translate(16, M.top + h / 2);
  ctx.rotate(-Math.PI / 2);
  drawRuns(ctx, y.symbol_runs, 0, 0);
  ctx.restore();
  // Stored bifurcation curves, clipped to the plot.
  ctx.save();
  ctx.beginPath();
  ctx.rect(M.left, M.top, w, h);
  ctx.clip();
  for (const c of S.curves) {
    ctx.strokeStyle = `rgb(${c.colour})`;
    ctx.lineWidth = Math.max(1.5, c.width_pt * 1.33);
    ctx.setLineDash(c.dash_pt[1] > 0 ? c.dash_pt.map((d) => d * 1.33) : []);
    ctx.beginPath();
    c.points.forEach(([px, py], i) => {
      const [cx, cy] = toCanvas(index(x, px), index(y, py));
      if (i === 0) ctx.moveTo(cx, cy); else ctx.lineTo(cx, cy);
    });
    ctx.stroke();
  }
  ctx.setLineDash([]);
  // Codimension-two points: white rings, as the figures mark them.
  for (const c of S.curves) {
    for (const [px, py] of c.marks) {
      const [cx, cy] = toCanvas(index(x, px), index(y, py));
      ctx.beginPath();
      ctx.arc(cx, cy, 4, 0, 2 * Math.PI);
      ctx.fillStyle = '#fff';
      ctx.fill();
      ctx.strokeStyle = '#000';
      ctx.lineWidth = 1;
      ctx.stroke();
    }
  }
  // The clicked cell, outlined: black, with a white line inside for dark labels.
  if (S.selected && S.selected.atlas === S.id) {
    const { ix, iy } = S.selected;
    const [ax, ay] = toCanvas(ix - 0.5, iy + 0.5), [bx, by] = toCanvas(ix + 0.5, iy - 0.5);
    ctx.lineWidth = 2;
    ctx.strokeStyle = '#000';
    ctx.strokeRect(ax, ay, bx - ax, by - ay);
    ctx.lineWidth = 1;
    ctx.strokeStyle = '#fff';
    ctx.strokeRect(ax + 1.5, ay + 1.5, bx - ax - 3, by - ay - 3);
  }
  // The box offered for a zoom, kept drawn until it is computed or the dialog closed.
  if (S.offered && S.offered.atlas === S.id && !S.drag) {
    const o = S.offered, [ax, ay] = toCanvas(o.x0, o.y1), [bx, by] = toCanvas(o.x1, o.y0);
    ctx.strokeStyle = '#000';
    ctx.lineWidth = 1.5;
    ctx.setLineDash([5, 3]);
    ctx.strokeRect(ax, ay, bx - ax, by - ay);
    ctx.setLineDash([]);
  }
  if (S.drag && S.drag.mode === 'box') {
    const d = S.drag;
    ctx.strokeStyle = '#000';
    ctx.lineWidth = 1.5;
    ctx.setLineDash([5, 3]);
    ctx.strokeRect(Math.min(d.x, d.cx), Math.min(d.y, d.cy), Math.abs(d.cx - d.x), Math.abs(d.cy - d.y));
    ctx.setLineDash([]);
  }
  ctx.restore();
  canvas.dataset.plot = JSON.stringify({ left: M.left, top: M.top, width: w, height: h, ...b });
}

function links() {
  const f = $('fig-format').value, size = $('fig-size').value, curves = $('curves').checked ? '&curves=1' : '';
  $('save-figure').href = `/api/figure?${query()}&format=${f}&size=${size}${curves}`;
  $('save-file').href = `/api/files/${S.id}`;
}

function eventCell(e) {
  const r = canvas.getBoundingClientRect();
  const cx = ((e.clientX - r.left) * canvas.width) / r.width, cy = ((e.clientY - r.top) * canvas.height) / r.height;
  const [fx, fy] = toCell(cx, cy);
  const { x, y } = S.info;
  const ix = Math.round(fx), iy = Math.round(fy);
  const inside = ix >= 0 && iy >= 0 && ix < x.count && iy < y.count && cx >= M.left && cy >= M.top;
  return { cx, cy, ix, iy, inside };
}

// A symbol as the figures write it (`render`'s runs from the API): each
// subscript run at three quarters of the size and a third of an em lower,
// the whole centred on (cx, y), in the context's font and colour.
function drawRuns(ctx, runs, cx, y) {
  const size = parseFloat(ctx.font);
  const font = ctx.font;
  const fontOf = (sub) => (sub ? font.replace(`${size}px`, `${0.75 * size}px`) : font);
  ctx.save();
  const widths = runs.map(([text, sub]) => {
    ctx.font = fontOf(sub);
    return ctx.measureText(text).width;
  });
  let left = cx - widths.reduce((a, b) => a + b, 0) / 2;
  ctx.textAlign = 'left';
  runs.forEach(([text, sub], i) => {
    ctx.font = fontOf(sub);
    ctx.fillText(text, left, sub ? y + size / 3 : y);
    left += widths[i];
  });
  ctx.restore();
}

// The plane's parameters of a cell, x first, by their symbols.
function parameters(values) {
  const { x, y } = S.info;
  return `${x.symbol} = ${short(values[x.name])}, ${y.symbol} = ${short(values[y.name])}`;
}

// The hover's text: the cell's parameters, then per sweep its labels, class
// and largest |multiplier| or λ (and the viewed quantity), then a table of
// every stored quantity, a column per sweep.
function describe(at) {
  const lines = [parameters(at.parameters)];
  // The quantity of the view, when it shows one (NAME:SWEEP).
  // Split at the last colon, as the server does: a mass may be named `M:down`.
  const viewed = S.view.includes(':') ? S.view.slice(0, S.view.lastIndexOf(':')) : null;
  const names = [];
  for (const sweep of S.info.sweeps) {
    const c = at.sweeps[sweep];
    if (!c) { lines.push(`${sweep}: not computed`); continue; }
    const labels = Object.entries(c.labels).map(([m, l]) => `${m} ${l}`).join(', ');
    const number = c.max_multiplier !== null ? `max |μ| ${short(c.max_multiplier)}`
      : c.lyapunov !== null ? `λ ${short(c.lyapunov)}` : '';
    lines.push(`${sweep}: ${labels} (${c.class}${number ? '; ' + number : ''})`);
    // null where the cell's motion could not be followed or none is stored.
    const quantities = c.quantities || {};
    if (viewed && Object.hasOwn(quantities, viewed)) {
      const v = quantities[viewed];
      lines.push(`  ${viewed} = ${v === null ? 'none' : short(v)}`);
    }
    if (c.reason) lines.push(`  ${c.reason}`);
    for (const n of Object.keys(quantities)) if (!names.includes(n)) names.push(n);
  }
  const text = el('div', lines.join('\n'));
  if (!names.length) return [text];
  const sweeps = S.info.sweeps.filter((s) => at.sweeps[s]);
  const cell = (t, tag = 'td') => el(tag, t);
  const head = el('tr', null, {}, [cell('', 'th'), ...sweeps.map((s) => cell(s, 'th'))]);
  const rows = names.map((n) => el('tr', null, { 'data-quantity': n }, [cell(n, 'th'), ...sweeps.map((s) => {
    const v = (at.sweeps[s].quantities || {})[n];
    return cell(v === null || v === undefined ? '—' : short(v));
  })]));
  return [text, el('table', null, { class: 'quantities' }, [head, ...rows])];
}

async function hover(e) {
  const c = eventCell(e);
  const tip = $('hover');
  if (!c.inside) { tip.hidden = true; S.hovered = null; return; }
  const key = `${S.id}:${c.ix}:${c.iy}`;
  tip.style.left = `${e.offsetX + 14}px`;
  tip.style.top = `${e.offsetY + 14}px`;
  if (key === S.hovered) return;
  S.hovered = key;
  try {
    const at = await getJSON(`/api/at?atlas=${S.id}&ix=${c.ix}&iy=${c.iy}`);
    if (S.hovered !== key) return;
    tip.replaceChildren(...describe(at));
    tip.hidden = false;
    // Within the plot's height: the table of quantities is tall.
    tip.style.top = `${Math.max(0, Math.min(e.offsetY + 14, canvas.clientHeight - tip.offsetHeight))}px`;
  } catch (err) { say(err.message); }
}

function sweepOfView() {
  const sweeps = S.info.sweeps;
  const named = S.view.includes(':') ? S.view.slice(S.view.lastIndexOf(':') + 1) : S.view;
  return sweeps.includes(named) ? named : sweeps.includes('up') ? 'up' : sweeps[0];
}

async function showCell(ix, iy, sweep) {
  S.selected = { atlas: S.id, ix, iy };
  draw();
  const panel = $('cell');
  panel.hidden = false;
  panel.dataset.state = 'loading';
  panel.replaceChildren(el('p', 'computing the cell…'));
  try {
    const at = await getJSON(`/api/at?atlas=${S.id}&ix=${ix}&iy=${iy}`);
    // The plane's values under `at.`: a parameter may be named as a key of the route (`sweep`, `n`).
    const q = `atlas=${S.id}&sweep=${encodeURIComponent(sweep)}&` + Object.entries(at.parameters).map(([k, v]) => `at.${encodeURIComponent(k)}=${v}`).join('&');
    const c = await getJSON('/api/cell?' + q);
    panel.dataset.json = JSON.stringify(c);
    panel.dataset.query = q;
    const others = S.info.sweeps.filter((s) => s !== sweep).flatMap((s) => [el('button', s, { 'data-sweep': s }), ' ']);
    const rows = [
      ['class', c.class + (c.n ? `, n = ${c.n}` : '') + (c.symmetry ? `, ${c.symmetry}` : '')],
      ...Object.entries(c.labels).map(([m, l]) => [`label ${m}`, l]),
      ['max |multiplier|', c.max_multiplier === null ? '—' : c.max_multiplier.toFixed(6)],
      ['Lyapunov', c.lyapunov === null ? '—' : `${c.lyapunov.toFixed(6)} per unit time`],
      ['impacts', Object.entries(c.impacts).map(([s, n]) => `${s} ${n}`).join(', ')],
      ['chatter', Object.entries(c.chatter).filter(([, v]) => v).map(([s]) => s).join(', ') || 'none'],
      ['sticking', Object.entries(c.sticking).filter(([, v]) => v).map(([s]) => s).join(', ') || 'none'],
      ['work', `${c.periods_simulated} periods, ${c.events} events`],
    ];
    if (c.reason) rows.push(['reason', c.reason]);
    const picture = (what, alt) => el('a', null, { href: `/api/cell/${what}.png?${q}`, target: '_blank' }, [el('img', null, { alt, src: `/api/cell/${what}.png?${q}` })]);
    panel.replaceChildren(
      el('h3', `${parameters(c.from.cell)} (${sweep} sweep)`),
      el('p', 'other sweeps: ', {}, others.length ? others : ['none']),
      el('table', null, {}, rows.map(([a, b]) => el('tr', null, {}, [el('th', a), el('td', b, { class: 'v', 'data-key': a })]))),
      el('div', null, { class: 'pictures' }, [picture('portrait', 'phase portraits and time series'), picture('sections', 'Poincaré sections')]),
      el('p', null, {}, [el('button', 'coexisting attractors', { id: 'attractors' }), ' ', el('button', 'basins', { id: 'basins' })]),
      el('div', null, { id: 'attractor-list' }),
      el('div', null, { id: 'basin-box' }),
    );
    panel.querySelectorAll('button[data-sweep]').forEach((b) => b.addEventListener('click', () => showCell(ix, iy, b.dataset.sweep)));
    $('attractors').addEventListener('click', () => attractors(q));
    $('basins').addEventListener('click', () => planBasins(q));
    panel.dataset.state = 'done';
    if (c.class === 'periodic') multipliers(q);
  } catch (err) {
    panel.dataset.state = 'failed';
    panel.textContent = err.message;
  }
}

// The Floquet multipliers of a periodic cell's orbit (Newton's method), a row of the table.
async function multipliers(q) {
  const row = document.createElement('tr');
  row.append(el('th', 'Floquet multipliers'), el('td', 'solving the orbit…'));
  $('cell').querySelector('table').appendChild(row);
  try {
    const o = await getJSON('/api/orbit?' + q);
    const mu = o.multipliers.map((m) => (Math.abs(m.im) > 1e-12 ? `${short(m.re)} ${m.im < 0 ? '−' : '+'} ${short(Math.abs(m.im))}i` : short(m.re)));
    row.lastChild.textContent = `${mu.join(', ')} (${o.stable ? 'stable' : 'unstable'}; period ${o.n})`;
  } catch (err) { row.lastChild.textContent = err.message; }
}

async function attractors(q) {
  const list = $('attractor-list');
  list.textContent = 'sampling 64 start states…';
  try {
    const a = await getJSON('/api/attractors?' + q);
    list.replaceChildren();
    a.attractors.forEach((at, i) => {
      const d = document.createElement('div');
      d.className = 'attractor';
      const labels = Object.entries(at.labels).map(([m, l]) => `${m} ${l}`).join(', ');
      d.append(swatch({ swatch: 'fill', colours: [a.colours[i]] }), document.createTextNode(`${(100 * at.fraction).toFixed(1)} %  ${labels} (${at.class})`));
      list.appendChild(d);
    });
    const img = document.createElement('img');
    img.alt = 'basins of attraction';
    img.src = 'data:image/png;base64,' + a.basins_png;
    list.appendChild(img);
  } catch (err) { list.textContent = err.message; }
}

// Seconds as people read them.
function seconds(t) { return t < 90 ? `${t.toPrecision(2)} s` : `${(t / 60).toPrecision(2)} min`; }

// The COUNT of an axis NAME=START:STOP:COUNT as typed (0 when it is not one).
function axisCount(text) {
  const m = /=[^:]+:[^:]+:\s*(\d+)\s*$/.exec(text);
  return m ? +m[1] : 0;
}

// The basins of the cell: a proposed grid (the server times the cell: each
// start costs about as much), editable, with its estimate; then the map.
async function planBasins(q) {
  const box = $('basin-box');
  box.dataset.state = 'planning';
  box.textContent = 'timing the cell for an estimate…';
  try {
    const p = await getJSON('/api/basins/plan?' + q);
    const x = el('input', null, { id: 'basin-x', size: 30, 'aria-label': 'horizontal axis of starts' });
    const y = el('input', null, { id: 'basin-y', size: 30, 'aria-label': 'vertical axis of starts' });
    x.value = p.x;
    y.value = p.y;
    const estimate = el('span', null, { id: 'basin-estimate' });
    const run = el('button', 'compute basins', { id: 'basin-run' });
    const update = () => {
      const n = axisCount(x.value) * axisCount(y.value);
      run.disabled = !(n > 0 && n <= p.max_starts);
      estimate.textContent = n > p.max_starts ? `${n} starts: at most ${p.max_starts} here (vibroatlas basins computes more)`
        : n > 0 ? `${n} starts, about ${seconds((n * p.seconds_per_start) / p.threads)} on ${p.threads} threads` : 'COMPONENT=START:STOP:COUNT';
    };
    x.addEventListener('input', update);
    y.addEventListener('input', update);
    update();
    run.addEventListener('click', () => basins(q, x.value, y.value));
    box.replaceChildren(
      el('p', `components ${p.components.join(', ')}: two over a grid of starts, the others at the cell's final state`),
      el('p', null, {}, [el('label', 'x ', {}, [x]), ' ', el('label', 'y ', {}, [y])]),
      el('p', null, {}, [run, ' ', estimate]),
      el('div', null, { id: 'basin-list' }),
    );
    box.dataset.state = 'planned';
  } catch (err) { box.dataset.state = 'failed'; box.textContent = err.message; }
}

async function basins(q, x, y) {
  const list = $('basin-list'), box = $('basin-box');
  box.dataset.state = 'running';
  list.textContent = 'computing the basins…';
  try {
    const b = await getJSON(`/api/basins?${q}&basin_x=${encodeURIComponent(x)}&basin_y=${encodeURIComponent(y)}`);
    box.dataset.json = JSON.stringify(b);
    const rows = b.attractors.map((at, i) => {
      const labels = Object.entries(at.labels).map(([m, l]) => `${m} ${l}`).join(', ');
      return el('div', null, { class: 'attractor' }, [swatch({ swatch: 'fill', colours: [b.colours[i]] }),
        `${(100 * at.fraction).toFixed(1)} %  ${labels}${at.symmetry ? ' ' + at.symmetry : ''} (${at.class})`]);
    });
    const e = b.boundary;
    const alpha = e.uncertainty_exponent === null ? 'none' : e.uncertainty_exponent.toFixed(3);
    rows.push(el('p', `basin entropy ${e.basin_entropy.toFixed(4)}, boundary ${e.boundary_basin_entropy.toFixed(4)} (fractal by ln 2: ${e.fractal ? 'yes' : 'no'}); uncertainty exponent ${alpha}; ${b.starts} starts in ${seconds(b.seconds)}`));
    list.replaceChildren(...rows);
    const pictures = $('cell').querySelector('.pictures');
    pictures.querySelector('.basins')?.remove();
    const src = 'data:image/png;base64,' + b.png;
    pictures.appendChild(el('div', null, { class: 'basins' }, [el('img', null, { alt: 'basins of attraction', src })]));
    box.dataset.state = 'done';
  } catch (err) { box.dataset.state = 'failed'; list.textContent = err.message; }
}

// The zoom dialog for a box dragged between two canvas points.
function offerZoom(d) {
  const { x, y } = S.info;
  const [ax, ay] = toCell(Math.min(d.x, d.cx), Math.max(d.y, d.cy));
  const [bx, by] = toCell(Math.max(d.x, d.cx), Math.min(d.y, d.cy));
  const clampX = (f) => Math.min(Math.max(f, 0), x.count - 1), clampY = (f) => Math.min(Math.max(f, 0), y.count - 1);
  const [x0, x1, y0, y1] = [clampX(ax), clampX(bx), clampY(ay), clampY(by)];
  if (x1 <= x0 || y1 <= y0) return;
  S.offered = { atlas: S.id, x0, x1, y0, y1 };
  draw();
  // At most 3 times finer than this map per axis, and no more cells than the screen shows of the box.
  const finer = (span, pixels) => Math.max(2, Math.min(Math.round(pixels), Math.round(3 * span) + 1));
  const nx = finer(x1 - x0, Math.abs(d.cx - d.x)), ny = finer(y1 - y0, Math.abs(d.cy - d.y));
  $('zoom-x').value = `${x.name}=${short(value(x, x0))}:${short(value(x, x1))}:${nx}`;
  $('zoom-y').value = `${y.name}=${short(value(y, y0))}:${short(value(y, y1))}:${ny}`;
  $('zoom-dialog').hidden = false;
  $('zoom-dialog').scrollIntoView({ block: 'nearest' });
  $('progress').value = 0;
  $('progress').dataset.state = 'idle';
  $('progress-text').textContent = '';
  estimateZoom();
}

// The zoom's estimated time: the server times a 3 × 3 zoom of the box; the
// estimate follows the counts typed.
async function estimateZoom() {
  const out = $('zoom-estimate');
  out.dataset.state = 'timing';
  out.textContent = 'timing a 3 × 3 zoom of the box for an estimate…';
  try {
    const q = ['x', 'y', 'set'].map((k) => `&${k}=${encodeURIComponent($('zoom-' + k).value)}`).join('');
    const p = await getJSON(`/api/zoom/plan?atlas=${S.id}${q}`);
    const update = () => {
      const n = axisCount($('zoom-x').value) * axisCount($('zoom-y').value);
      const t = p.overhead_seconds + (n * p.sweeps * p.seconds_per_cell) / p.threads;
      out.dataset.seconds = t;
      out.textContent = n > 0 ? `${n} cells × ${p.sweeps} sweep${p.sweeps > 1 ? 's' : ''}, about ${seconds(t)} on ${p.threads} threads` : 'NAME=START:STOP:COUNT';
    };
    $('zoom-x').oninput = update;
    $('zoom-y').oninput = update;
    // Another parameter value costs what it costs: timed again.
    $('zoom-set').onchange = estimateZoom;
    update();
    out.dataset.state = 'done';
  } catch (err) { out.dataset.state = 'failed'; out.textContent = err.message; }
}

// Runs the zoom of box (x, y) of atlas `atlas` (at the parameters `set`,
// NAME=VALUE,…, when not empty) with its progress shown; the child's id once
// done (an error when it failed or was cancelled).
async function zoomJob(atlas, x, y, set) {
  const progress = $('progress');
  const body = JSON.stringify(set.trim() ? { atlas, x, y, set: set.trim() } : { atlas, x, y });
  const { job } = await getJSON('/api/zoom', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body });
  S.job = job;
  progress.dataset.state = 'running';
  $('zoom-cancel').hidden = false;
  try {
    for (;;) {
      const j = await getJSON(`/api/jobs/${job}`);
      progress.value = j.progress;
      $('progress-text').textContent = `${(100 * j.progress).toFixed(0)} %`;
      if (j.state === 'running') { await new Promise((r) => setTimeout(r, 250)); continue; }
      $('progress-text').textContent = `${j.state} in ${seconds(j.seconds)}`;
      progress.dataset.seconds = j.seconds;
      if (j.state === 'done') return j.child;
      progress.dataset.state = j.state;
      throw new Error(j.state === 'failed' ? j.error : 'the zoom was cancelled');
    }
  } finally {
    $('zoom-cancel').hidden = true;
    S.job = null;
  }
}

async function runZoom() {
  say('');
  const progress = $('progress');
  try {
    const child = await zoomJob(S.id, $('zoom-x').value, $('zoom-y').value, $('zoom-set').value);
    S.offered = null;
    await load({ atlas: child, view: S.view, mass: S.mass }, true);
    progress.dataset.state = 'done';
  } catch (err) {
    if (progress.dataset.state === 'running' || progress.dataset.state === 'idle') progress.dataset.state = 'failed';
    say(err.message);
  }
}

canvas.addEventListener('mousedown', (e) => {
  const c = eventCell(e);
  S.drag = { x: c.cx, y: c.cy, cx: c.cx, cy: c.cy, mode: e.shiftKey || e.button === 1 ? 'pan' : 'box', box: { ...S.box } };
});
canvas.addEventListener('mousemove', (e) => {
  if (!S.drag) { hover(e); return; }
  const c = eventCell(e);
  const d = S.drag;
  d.cx = c.cx;
  d.cy = c.cy;
  if (d.mode === 'pan') {
    const { w, h } = plotSize(), b = d.box;
    const dx = ((c.cx - d.x) / w) * (b.x1 - b.x0), dy = ((c.cy - d.y) / h) * (b.y1 - b.y0);
    S.box = { x0: b.x0 - dx, x1: b.x1 - dx, y0: b.y0 + dy, y1: b.y1 + dy };
  }
  draw();
});
window.addEventListener('mouseup', (e) => {
  const d = S.drag;
  if (!d) return;
  S.drag = null;
  const moved = Math.hypot(d.cx - d.x, d.cy - d.y);
  if (d.mode === 'pan') { toAddress(false); draw(); return; }
  if (moved < 4) {
    const c = eventCell(e);
    if (c.inside) showCell(c.ix, c.iy, sweepOfView());
  } else {
    offerZoom(d);
  }
  draw();
});
canvas.addEventListener('mouseleave', () => { $('hover').hidden = true; S.hovered = null; });
canvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  const c = eventCell(e), [fx, fy] = toCell(c.cx, c.cy), f = e.deltaY > 0 ? 1.25 : 0.8, b = S.box;
  S.box = { x0: fx - (fx - b.x0) * f, x1: fx + (b.x1 - fx) * f, y0: fy - (fy - b.y0) * f, y1: fy + (b.y1 - fy) * f };
  draw();
  toAddress(false);
}, { passive: false });
canvas.addEventListener('dblclick', () => { S.box = whole(); draw(); toAddress(false); });
$('reset').addEventListener('click', () => { S.box = whole(); draw(); toAddress(false); });
$('view').addEventListener('change', async () => { S.view = $('view').value; await layer(); toAddress(false); });
$('mass').addEventListener('change', async () => { S.mass = $('mass').value; await layer(); toAddress(false); });
$('curves').addEventListener('change', () => layer().catch((e) => say(e.message)));
$('fig-format').addEventListener('change', links);
$('fig-size').addEventListener('change', links);
$('back').addEventListener('click', () => history.back());
$('forward').addEventListener('click', () => history.forward());
$('zoom-run').addEventListener('click', runZoom);
$('zoom-close').addEventListener('click', () => { $('zoom-dialog').hidden = true; S.offered = null; draw(); });
$('zoom-cancel').addEventListener('click', () => { if (S.job !== null) fetch(`/api/jobs/${S.job}`, { method: 'DELETE' }); });
window.addEventListener('popstate', () => load(fromAddress(), false).catch((e) => say(e.message)));

// For scripts and tests: the canvas pixel at the centre of cell (ix, iy).
window.vibroatlas = { cellCentre: (ix, iy) => toCanvas(ix, iy), state: S, draw };

load(fromAddress(), false).catch((e) => say(e.message));
