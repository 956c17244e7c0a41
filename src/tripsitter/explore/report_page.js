// The report's script (report_page.js, inlined into index.html by report.cpp): draws every chart and table from
// the JSON in #report-data, {sweep, summary, board, columns, rows, thumbnails}, where each row holds a point's
// values in the order of columns (point.h). Any summary or sweep entry may be absent or null. When it has drawn,
// it checks each chart's canvas has ink and says so on <body> for tests: data-charts-expected,
// data-charts-drawn, data-ready="1" (and data-error when something failed).
(function () {
  'use strict';

  // Names for axes and headings where a column's own name is terse.
  const LABELS = {
    workers: 'workers', frac_bits: 'fractional bits', sqrt_iterations: 'square-root iterations', spp: 'samples per pixel',
    late_lines: 'late lines', fps: 'frames per second', dsp: 'DSP48E1 slices', bram_kbit: 'block RAM',
    differing_percent: 'pixels differing', relmse: 'relMSE',
  };
  const PALETTE = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#e377c2', '#17becf', '#7f7f7f',
                   '#bcbd22'];
  const STYLES = ['circle', 'triangle', 'rect', 'rectRot', 'star', 'crossRot'];
  const FITS = '#1a7f37';
  const DOES_NOT_FIT = '#d62728';
  const MAX_SERIES_SHOWN = 12;  // more start hidden: a click on the legend shows them

  const body = document.body;
  const charts = [];  // every canvas given to Chart.js, for the self-check
  const problems = [];

  // ---- small helpers ----

  function el(tag, attrs, children) {
    const node = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (v === undefined || v === null || v === false) continue;
      if (k === 'class') node.className = v;
      else if (k === 'text') node.textContent = v;
      else node.setAttribute(k, v === true ? '' : String(v));
    }
    for (const c of [].concat(children === undefined ? [] : children)) {
      if (c === null || c === undefined || c === false) continue;
      node.appendChild(typeof c === 'object' ? c : document.createTextNode(String(c)));
    }
    return node;
  }
  const isNum = (v) => typeof v === 'number' && Number.isFinite(v);
  const arr = (v) => (Array.isArray(v) ? v : []);
  const obj = (v) => (v && typeof v === 'object' && !Array.isArray(v) ? v : {});
  const note = (text) => el('p', {class: 'note', text});

  function fmt(v) {
    if (v === null || v === undefined) return '\u2013';
    if (typeof v === 'boolean') return v ? 'yes' : 'no';
    if (typeof v !== 'number') return String(v);
    if (!Number.isFinite(v)) return String(v);
    if (Number.isInteger(v)) return String(v);
    const a = Math.abs(v);
    if (a !== 0 && a < 1e-3) return v.toExponential(2);
    if (a >= 1e5) return v.toFixed(0);
    return String(Number(v.toPrecision(4)));
  }

  function safely(what, f) {
    try {
      f();
    } catch (e) {
      problems.push(what + ': ' + (e && e.stack ? e.stack : String(e)));
    }
  }

  // ---- the data ----

  let data = {};
  try {
    data = obj(JSON.parse(document.getElementById('report-data').textContent));
  } catch (e) {
    problems.push('the report\'s data does not parse: ' + e);
  }
  const columns = arr(data.columns).filter((c) => c && typeof c.name === 'string');
  const colByName = new Map(columns.map((c) => [c.name, c]));
  const points = arr(data.rows).map((row) => {
    const p = {};
    columns.forEach((c, i) => { p[c.name] = Array.isArray(row) && row[i] !== undefined ? row[i] : null; });
    return p;
  });
  const byIndex = new Map(points.map((p) => [p.index, p]));
  const summary = obj(data.summary);
  const sweep = obj(data.sweep);
  const board = obj(data.board);
  // The columns of a point's configuration (the data marks them: point.h's Column::configuration): series group
  // points that share all of them but the chart's x.
  const config = columns.filter((c) => c.configuration === true).map((c) => c.name);
  const isPath = (p) => isNum(p.spp) && p.spp > 0;
  const scenes = [...new Set(points.map((p) => p.scene))];
  // For each preset, the configuration columns that take more than one value among its points: what tells them
  // apart (a column that differs only from preset to preset, as the SPI clock may, is said by the preset's name).
  function varyingByPreset(pts, cols) {
    const byPreset = new Map();
    for (const p of pts) {
      if (!byPreset.has(p.preset)) byPreset.set(p.preset, []);
      byPreset.get(p.preset).push(p);
    }
    const varying = new Map();
    for (const [preset, group] of byPreset) {
      varying.set(preset, cols.filter((c) => new Set(group.map((p) => JSON.stringify(p[c]))).size > 1));
    }
    return varying;
  }
  const sweptByPreset = varyingByPreset(points, config.filter((c) => c !== 'scene' && c !== 'preset'));
  const swept = config.filter((c) => [...sweptByPreset.values()].some((cols) => cols.includes(c)));

  function unit(name) { const c = colByName.get(name); return c && c.unit ? c.unit : ''; }
  function axisTitle(name) {
    const label = LABELS[name] || name;
    const u = unit(name);
    return u && !label.includes(u) ? label + ' (' + u + ')' : label;
  }
  // A point's configuration in a line: its preset and the swept columns it has values for.
  function configText(p, withScene) {
    const parts = [];
    if (withScene) parts.push(p.scene);
    parts.push(p.preset);
    for (const c of sweptByPreset.get(p.preset) || []) {
      if (p[c] === null || p[c] === undefined) continue;
      parts.push(c + '=' + fmt(p[c]));
    }
    return parts.join(', ');
  }
  function errorText(p) {
    if (isPath(p)) return isNum(p.relmse) ? 'relMSE ' + fmt(p.relmse) : '\u2013';
    return isNum(p.differing_percent) ? fmt(p.differing_percent) + ' % differing' : '\u2013';
  }
  const pointLink = (i) => el('a', {href: '#point-' + i, text: '#' + i});

  // ---- charts ----

  // Whether values span decades enough for a log axis (all positive, largest / smallest >= ratio).
  function spans(values, ratio) {
    const v = values.filter(isNum);
    if (!v.length || v.some((x) => x <= 0)) return false;
    return Math.max(...v) / Math.min(...v) >= ratio;
  }

  // An axis for column `name` over `values`: log where they span decades; for a swept parameter on x (`exact`),
  // grid lines and labels at exactly the values swept, with a margin so no point sits on the frame.
  function axis(name, values, opts) {
    const o = opts || {};
    const v = values.filter(isNum);
    const log = o.log !== undefined ? o.log : spans(v, o.ratio || 50);
    const a = {
      type: log ? 'logarithmic' : 'linear',
      title: {display: true, text: o.title || axisTitle(name), font: {size: 13, weight: '600'}},
      ticks: {font: {size: 12}},
      grid: {color: '#e6e9ef'},
    };
    if (!log && o.zero) a.beginAtZero = true;
    if (!log) a.grace = '4%';  // no point drawn on the frame
    if (log && v.length && !o.exact) {
      a.min = Math.min(...v) / 1.5;
      a.max = Math.max(...v) * 1.5;
      // Labels at 1, 2 and 5 of each decade, in the page's number format; the other grid lines unlabelled.
      a.ticks.callback = (value) => {
        const r = value / Math.pow(10, Math.floor(Math.log10(value) + 1e-9));
        return [1, 2, 5].some((k) => Math.abs(r - k) < 1e-6) ? fmt(value) : '';
      };
    }
    if (o.exact && v.length) {
      let xs = [...new Set(v)].sort((p, q) => p - q);
      const lo = xs[0], hi = xs[xs.length - 1];
      if (log) {
        a.min = lo / 1.3;
        a.max = hi * 1.3;
      } else {
        const pad = hi > lo ? (hi - lo) * 0.06 : Math.max(1, Math.abs(lo) * 0.1);
        a.min = lo - pad;
        a.max = hi + pad;
      }
      // At most about 14 labels, spaced evenly on the axis as drawn (in log space on a log axis), the last kept.
      const at = (x) => (log ? Math.log(x) : x);
      const gap = (at(hi) - at(lo)) / 14;
      if (xs.length > 14 && gap > 0) {
        const kept = [];
        for (const x of xs) if (!kept.length || at(x) - at(kept[kept.length - 1]) >= gap) kept.push(x);
        if (kept[kept.length - 1] !== hi) {
          if (at(hi) - at(kept[kept.length - 1]) < gap / 2) kept.pop();
          kept.push(hi);
        }
        xs = kept;
      }
      a.afterBuildTicks = (scale) => { scale.ticks = xs.map((x) => ({value: x})); };
      a.ticks.callback = (value) => fmt(value);
      a.ticks.autoSkip = false;
      a.ticks.maxRotation = 0;
    }
    return a;
  }

  // Series of y against x: one per group of points equal in every configuration column but x (and with
  // opts.keep only), joined when their curves coincide (say workers, which do not change the picture). Labelled
  // by scene (unless the chart is one scene's), preset, and the columns that differ between groups.
  function seriesOf(pts, x, y, opts) {
    const o = opts || {};
    const keys = config.filter((c) => c !== x);
    const groups = new Map();
    let dropped = 0;
    for (const p of pts) {
      if (!isNum(p[x]) || !isNum(p[y])) continue;
      if ((o.logX && p[x] <= 0) || (o.logY && p[y] <= 0)) { dropped++; continue; }
      const key = JSON.stringify(keys.map((c) => p[c]));
      if (!groups.has(key)) groups.set(key, {first: p, pts: []});
      groups.get(key).pts.push(p);
    }
    // A group with a single x is no curve: left out while any group has two or more (a sweep of one parameter
    // beside a sweep of another meets each point of the other sweep once).
    let all = [...groups.values()];
    const curvesOnly = all.filter((g) => new Set(g.pts.map((p) => p[x])).size >= 2);
    const single = curvesOnly.length ? all.length - curvesOnly.length : 0;
    if (curvesOnly.length) all = curvesOnly;
    const varying = varyingByPreset(all.map((g) => g.first), keys.filter((c) => c !== 'scene' && c !== 'preset'));
    const curves = new Map();
    for (const g of all) {
      g.pts.sort((p, q) => p[x] - q[x]);
      const curve = JSON.stringify([g.first.scene, g.first.preset, g.pts.map((p) => [p[x], p[y]])]);
      if (curves.has(curve)) curves.get(curve).members.push(g.first);
      else curves.set(curve, Object.assign(g, {members: [g.first]}));
    }
    const list = [...curves.values()];
    list.forEach((g, n) => {
      const parts = [];
      if (!o.oneScene) parts.push(g.first.scene);
      parts.push(g.first.preset);
      for (const c of varying.get(g.first.preset) || []) {
        const values = [...new Set(g.members.map((m) => m[c]).filter((v) => v !== null && v !== undefined))];
        if (!values.length) continue;
        values.sort((p, q) => (isNum(p) && isNum(q) ? p - q : String(p).localeCompare(String(q))));
        const shown = values.length <= 4 ? values.map(fmt).join('/') : fmt(values[0]) + '..' + fmt(values[values.length - 1]);
        parts.push(c + '=' + shown);
      }
      const label = parts.join(', ');
      g.label = label.length > 64 ? label.slice(0, 62) + '\u2026' : label;  // legends do not wrap; tooltips say all
      g.colour = PALETTE[n % PALETTE.length];
      g.style = STYLES[Math.floor(n / PALETTE.length) % STYLES.length];
    });
    return {series: list, dropped, single};
  }

  // A card holding one chart (or, when there is nothing to draw, a note saying why).
  function card(parent, title, height) {
    const c = el('div', {class: 'chart-card'}, [el('h4', {text: title})]);
    parent.appendChild(c);
    const box = el('div', {class: 'box', style: 'height:' + height + 'px'});
    c.appendChild(box);
    return {card: c, box};
  }
  function caption(c, text) { c.card.appendChild(el('p', {class: 'caption', text})); }

  function draw(c, config) {
    const canvas = el('canvas', {role: 'img', 'aria-label': c.card.querySelector('h4').textContent});
    c.box.appendChild(canvas);
    config.options = Object.assign({
      animation: false,
      responsive: true,
      maintainAspectRatio: false,
      normalized: true,
    }, config.options || {});
    const chart = new Chart(canvas.getContext('2d'), config);
    charts.push({canvas, chart});
    return chart;
  }

  function legend(count) {
    return {
      display: count > 0,
      position: 'bottom',
      labels: {usePointStyle: true, boxWidth: 8, boxHeight: 8, padding: 10, font: {size: 12}},
    };
  }
  // Room for the plot (about 300 pixels) and its legend below, which Chart.js packs into rows as wide as the chart:
  // the rows counted from the labels' widths in the legend's font, so a long legend never squeezes the plot.
  const measure = document.createElement('canvas').getContext('2d');
  function fitHeight(c, labels) {
    measure.font = '12px ' + Chart.defaults.font.family;
    const width = Math.max(200, c.box.clientWidth - 16);
    let rows = labels.length ? 1 : 0, used = 0;
    for (const label of labels) {
      const w = measure.measureText(label).width + 30;  // the marker, its gap and the padding between items
      if (used > 0 && used + w > width) {
        rows++;
        used = 0;
      }
      used += w;
    }
    c.box.style.height = (310 + rows * 22) + 'px';
  }

  function tooltip(yName) {
    return {
      callbacks: {
        label: (ctx) => {
          const p = byIndex.get(ctx.raw && ctx.raw.i);
          if (!p) return ctx.dataset.label + ': ' + fmt(ctx.parsed.y);
          return ['#' + p.index + ' ' + configText(p, true), (LABELS[yName] || yName) + ': ' + fmt(p[yName])];
        },
      },
    };
  }

  // y against x, one line per series, into `parent`; a note instead when no point has both values.
  function curveChart(parent, title, pts, x, y, opts) {
    const o = opts || {};
    const xs = pts.map((p) => p[x]).filter(isNum);
    const ys = pts.map((p) => p[y]).filter(isNum);
    const logX = spans(xs, 16);
    const logY = o.logY !== undefined ? o.logY : spans(ys, 50);
    const {series, dropped, single} = seriesOf(pts, x, y, {oneScene: o.oneScene, logX, logY});
    if (!series.length) {
      const c = el('div', {class: 'chart-card'}, [el('h4', {text: title}), note(o.empty || 'No point has both ' + x + ' and ' + y + '.')]);
      parent.appendChild(c);
      return;
    }
    const c = card(parent, title, 310);
    fitHeight(c, series.map((g) => g.label));
    const shownPts = series.flatMap((g) => g.pts);
    const shownXs = shownPts.map((p) => p[x]).filter(isNum);
    const shownYs = shownPts.map((p) => p[y]).filter(isNum);
    draw(c, {
      type: 'scatter',
      data: {
        datasets: series.map((g, n) => ({
          label: g.label,
          data: g.pts.map((p) => ({x: p[x], y: p[y], i: p.index})),
          showLine: true,
          borderColor: g.colour,
          backgroundColor: g.colour,
          pointStyle: g.style,
          pointRadius: 4,
          pointHoverRadius: 6,
          borderWidth: 2,
          hidden: n >= MAX_SERIES_SHOWN,
        })),
      },
      options: {
        scales: {
          x: axis(x, shownXs.filter((v) => !logX || v > 0), {exact: true, log: logX}),
          y: axis(y, shownYs, {log: logY, zero: true}),
        },
        plugins: {legend: legend(series.length), tooltip: tooltip(y)},
      },
    });
    const distinct = new Set(xs).size;
    if (distinct === 1) caption(c, 'Only one value of ' + x + ' (' + fmt(xs[0]) + ') in this sweep: sweep it for a curve.');
    if (series.length > MAX_SERIES_SHOWN) {
      caption(c, series.length + ' series; the first ' + MAX_SERIES_SHOWN + ' are shown, click a legend entry to show or hide one.');
    }
    if (dropped) caption(c, dropped + ' point(s) with a value of 0 are not on this log scale.');
    if (single) caption(c, single + ' point(s) whose configuration meets only one value of ' + x + ' are left out.');
  }

  // The points no other point beats on both: lower or equal dsp and error, one of them lower.
  function paretoFront(pts) {
    const sorted = pts.slice().sort((p, q) => p.x - q.x || p.y - q.y);
    const front = [];
    let best = Infinity;
    for (const p of sorted) {
      if (p.y < best) {
        front.push(p);
        best = p.y;
      }
    }
    return front;
  }

  function paretoChart(parent, title, pts, yName) {
    const all = pts.filter((p) => isNum(p.dsp) && isNum(p[yName]))
      .map((p) => ({x: p.dsp, y: p[yName], i: p.index, fits: p.fits === true}));
    const logY = spans(all.map((p) => p.y), 50);
    const shown = logY ? all.filter((p) => p.y > 0) : all;
    if (!shown.length) {
      parent.appendChild(el('div', {class: 'chart-card'}, [el('h4', {text: title}), note('No point has both a DSP count and ' + yName + '.')]));
      return;
    }
    const front = paretoFront(shown);
    const datasets = [
      {label: 'Pareto front', data: front, showLine: true, borderColor: '#1d2330', backgroundColor: 'rgba(0,0,0,0)',
       pointRadius: 7, pointHoverRadius: 8, pointBorderWidth: 1.5, borderWidth: 2, order: 0},
      {label: 'fits the ' + (board.name || 'FPGA'), data: shown.filter((p) => p.fits), borderColor: FITS,
       backgroundColor: FITS, pointRadius: 4, pointStyle: 'circle', order: 1},
      {label: 'does not fit', data: shown.filter((p) => !p.fits), borderColor: DOES_NOT_FIT,
       backgroundColor: DOES_NOT_FIT, pointRadius: 5, pointStyle: 'crossRot', borderWidth: 2, order: 2},
    ];
    const dsps = shown.map((p) => p.x);
    const limit = board.dsp;
    // The board's DSP budget as a dashed vertical line, when the points come near it.
    if (isNum(limit) && Math.max(...dsps) >= 0.5 * limit) {
      const ys = shown.map((p) => p.y);
      datasets.push({label: (board.name || 'board') + ': ' + limit + ' DSPs', data: [{x: limit, y: Math.min(...ys)}, {x: limit, y: Math.max(...ys)}],
                     showLine: true, borderColor: '#7f7f7f', borderDash: [6, 4], borderWidth: 1.5, pointRadius: 0,
                     pointHoverRadius: 0, pointStyle: 'line', order: 3});
    }
    const c = card(parent, title, 310);
    fitHeight(c, datasets.map((d) => d.label));
    draw(c, {
      type: 'scatter',
      data: {datasets},
      options: {
        scales: {x: axis('dsp', dsps, {log: false, zero: true}), y: axis(yName, shown.map((p) => p.y), {log: logY, zero: true})},
        plugins: {legend: legend(datasets.length), tooltip: tooltip(yName)},
      },
    });
    caption(c, front.length + ' of ' + shown.length + ' points on the front (circled): no other point has as few DSPs and as little error.' +
                (all.length > shown.length ? ' ' + (all.length - shown.length) + ' point(s) with no error are not on this log scale.' : ''));
  }

  function group(parent, id, title, what) {
    const g = el('div', {class: 'chart-group', id}, [el('h3', {text: title}), what ? el('p', {class: 'what', text: what}) : null]);
    const grid = el('div', {class: 'chart-grid'});
    g.appendChild(grid);
    parent.appendChild(g);
    return {group: g, grid};
  }

  function drawCharts() {
    const root = document.getElementById('charts-body');
    if (!points.length) {
      root.appendChild(note('No points in this report: nothing to chart.'));
      return;
    }
    const mirror = points.filter((p) => !isPath(p));
    const path = points.filter(isPath);

    // (1) Late lines against workers, one chart per scene.
    let g = group(root, 'late-lines', 'Late lines against workers',
                  'Lines with a late pixel in the last frame (0: every line meets its deadline), one line per ' +
                  'configuration that differs only in workers.');
    for (const s of scenes) {
      safely('late lines, ' + s, () => curveChart(g.grid, s + ': late lines against workers',
                                                  points.filter((p) => p.scene === s), 'workers', 'late_lines',
                                                  {oneScene: true, logY: false}));
    }

    // (2) Error against fractional bits: the mirror presets' percent of pixels, the path preset's relMSE.
    g = group(root, 'error', 'Error against fractional bits',
              'Mirror presets (wide, board-2023): percent of pixels that differ from the float reference. ' +
              'Path preset: relMSE of frame memory against the float path tracer. Separate charts: the two are ' +
              'not the same measure.');
    safely('error, mirror', () => {
      if (mirror.length) curveChart(g.grid, 'Mirror presets: pixels differing against fractional bits', mirror, 'frac_bits', 'differing_percent', {});
      else g.grid.appendChild(el('div', {class: 'chart-card'}, [el('h4', {text: 'Mirror presets'}), note('No mirror-preset (wide, board-2023) points in this sweep.')]));
    });
    safely('error, path', () => {
      if (path.length) curveChart(g.grid, 'Path preset: relMSE against fractional bits', path, 'frac_bits', 'relmse', {});
      else g.grid.appendChild(el('div', {class: 'chart-card'}, [el('h4', {text: 'Path preset'}), note('No path-preset points in this sweep.')]));
    });

    // (3) Frames per second against samples per pixel (path preset).
    g = group(root, 'fps', 'Frames per second against samples per pixel',
              'Path preset: complete new worlds per second the monitor could show, one line per configuration ' +
              'that differs only in samples per pixel.');
    safely('fps', () => {
      if (path.length) curveChart(g.grid, 'Path preset: frames per second against samples per pixel', path, 'spp', 'fps', {});
      else g.grid.appendChild(el('div', {class: 'chart-card'}, [el('h4', {text: 'Path preset'}), note('No path-preset points in this sweep: no samples per pixel to chart.')]));
    });

    // (4) Frames per second against the SPI clock: where the link, not the workers, limits the new worlds shown.
    g = group(root, 'link', 'Frames per second against the SPI clock',
              'Complete new worlds per second the monitor could show: at most one world per time it takes on the ' +
              'wire. One line per configuration that differs only in the SPI clock.');
    safely('link', () => curveChart(g.grid, 'Frames per second against the SPI clock', points, 'spi_mhz', 'fps',
                                    {empty: 'Only one SPI clock in this sweep: sweep spi for a curve.'}));

    // (5) DSPs against error: every point, coloured by whether it fits, and the Pareto front; per kind and scene.
    g = group(root, 'pareto', 'DSPs against error: the Pareto front',
              'Every point, green where it fits the ' + (board.name || 'FPGA') + '\u2019s DSPs and block RAM, red where ' +
              'not; the line joins the points no other point beats on both DSPs and error. One chart per scene, ' +
              'mirror and path presets apart.');
    for (const [kind, pts, yName, none] of [['Mirror presets', mirror, 'differing_percent', 'No mirror-preset (wide, board-2023) points in this sweep.'],
                                            ['Path preset', path, 'relmse', 'No path-preset points in this sweep.']]) {
      if (!pts.length) {
        g.grid.appendChild(el('div', {class: 'chart-card'}, [el('h4', {text: kind}), note(none)]));
        continue;
      }
      for (const s of scenes) {
        const mine = pts.filter((p) => p.scene === s);
        if (!mine.length) continue;
        safely('pareto, ' + kind + ', ' + s, () => paretoChart(g.grid, s + ', ' + kind.toLowerCase() + ': DSPs against ' +
                                                                 (yName === 'relmse' ? 'relMSE' : 'pixels differing'), mine, yName));
      }
    }
  }

  // ---- the sweep ----

  function drawSweep() {
    const root = document.getElementById('sweep-body');
    const dl = el('dl', {class: 'facts'});
    const row = (k, v) => { dl.appendChild(el('dt', {text: k})); dl.appendChild(el('dd', {}, v)); };
    if (typeof sweep.command === 'string' && sweep.command) row('Command', el('code', {text: sweep.command}));
    const sceneList = arr(sweep.scenes).length ? arr(sweep.scenes) : scenes;
    if (sceneList.length) row('Scenes', sceneList.map((s) => el('code', {text: String(s)})));
    if (arr(sweep.sweeps).length) row('Swept', arr(sweep.sweeps).map((s) => el('code', {text: String(s)})));
    const done = isNum(sweep.points_done) ? sweep.points_done : points.length;
    const planned = isNum(sweep.points_planned) ? sweep.points_planned : null;
    row('Points', [planned !== null ? done + ' of ' + planned + ' done' : done + ' done',
                   sweep.interrupted === true ? ' ' : null,
                   sweep.interrupted === true ? el('span', {class: 'badge bad', text: 'interrupted'}) : null]);
    if (isNum(sweep.seconds)) {
      const s = sweep.seconds;
      row('Time', s >= 120 ? Math.floor(s / 60) + ' min ' + Math.round(s % 60) + ' s' : fmt(Number(s.toFixed(1))) + ' s');
    }
    if (points.length) {
      const onTime = points.filter((p) => p.on_time === true).length;
      const fits = points.filter((p) => p.fits === true).length;
      row('On time', onTime + ' of ' + points.length + ' points meet every line deadline');
      row('Fit', fits + ' of ' + points.length + ' points fit the ' + (board.name || 'FPGA') +
                 (isNum(board.dsp) ? ' (' + board.dsp + ' DSPs, ' + fmt(board.bram_kbit) + ' Kbit block RAM)' : ''));
    }
    root.appendChild(dl);
  }

  // ---- the cheapest configurations ----

  const CHEAP_COLUMNS = ['workers', 'frac_bits', 'sqrt_iterations', 'bounces', 'spp', 'depth', 'dsp', 'bram_kbit', 'late_lines'];

  function headerCell(name, extra) {
    const c = colByName.get(name);
    return el('th', {class: extra || '', title: c ? c.description : ''}, [name, unit(name) ? el('span', {class: 'unit', text: unit(name)}) : null]);
  }
  function valueCell(name, v) {
    if (v === null || v === undefined) return el('td', {class: 'null', text: '\u2013'});
    if (typeof v === 'boolean') return el('td', {class: v ? 'yes' : 'no', text: v ? 'yes' : 'no'});
    return el('td', {class: typeof v === 'string' ? 'text' : '', text: fmt(v)});
  }

  function drawCheapest() {
    const root = document.getElementById('cheapest-body');
    const entries = arr(summary.cheapest_on_time).map(obj);
    if (!entries.length) {
      root.appendChild(note('The summary names no cheapest configuration.'));
    } else {
      root.appendChild(el('p', {class: 'what note', text: 'For each scene and preset, the summary\u2019s cheapest point that fits the ' + (board.name || 'FPGA') + ' and whose every line met its deadline.'}));
      const head = el('tr', {}, [el('th', {class: 'text', text: 'scene'}), el('th', {class: 'text', text: 'preset'}), el('th', {text: 'point'})]
        .concat(CHEAP_COLUMNS.map((n) => headerCell(n)), [el('th', {}, ['error', el('span', {class: 'unit', text: '% differing or relMSE'})]), headerCell('fits')]));
      const tbody = el('tbody');
      for (const e of entries) {
        const p = isNum(e.point) ? byIndex.get(e.point) : undefined;
        const scene = e.scene !== undefined && e.scene !== null ? String(e.scene) : p ? p.scene : '\u2013';
        const preset = e.preset !== undefined && e.preset !== null ? String(e.preset) : p ? p.preset : '\u2013';
        const cells = [el('td', {class: 'text', text: scene}), el('td', {class: 'text', text: preset})];
        if (!p) {
          const why = isNum(e.point) ? 'point #' + e.point + ' is not in this report' : 'none fits and is on time in this sweep';
          cells.push(el('td', {class: 'none', colspan: CHEAP_COLUMNS.length + 3, text: why}));
        } else {
          cells.push(el('td', {}, [pointLink(p.index)]));
          for (const n of CHEAP_COLUMNS) cells.push(valueCell(n, p[n]));
          cells.push(el('td', {text: errorText(p)}));
          cells.push(valueCell('fits', p.fits));
        }
        tbody.appendChild(el('tr', {}, cells));
      }
      root.appendChild(el('div', {class: 'table-wrap'}, [el('table', {}, [el('thead', {}, [head]), tbody])]));
    }

    const sixty = arr(summary.sixty_hz).map(obj);
    if (sixty.length) {
      root.appendChild(el('h3', {text: 'Sixty frames per second'}));
      const ul = el('ul', {class: 'lines'});
      for (const e of sixty) {
        const p = isNum(e.point) ? byIndex.get(e.point) : undefined;
        const scene = e.scene !== undefined && e.scene !== null ? String(e.scene) : p ? p.scene : 'all scenes';
        if (!p) {
          ul.appendChild(el('li', {}, [el('strong', {text: scene}), isNum(e.point) ? ': point #' + e.point + ' is not in this report' : ': none reaches 60 frames/s in this sweep']));
          continue;
        }
        ul.appendChild(el('li', {}, [el('strong', {text: scene}), ': ', pointLink(p.index), ' ' + configText(p, false) + ' \u2014 ' +
                                      fmt(p.fps) + ' frames/s, ' + fmt(p.dsp) + ' DSPs, ' + fmt(p.bram_kbit) + ' Kbit, ' + errorText(p)]));
      }
      root.appendChild(ul);
    }
  }

  // ---- all points ----

  function drawPoints() {
    const root = document.getElementById('points-body');
    if (!points.length) {
      root.appendChild(note('No points in this report.'));
      return;
    }
    root.appendChild(el('p', {class: 'note', text: points.length + ' points, every column of points.csv: what was swept and ' +
                          'the verdicts first. Click a column\u2019s name to sort by it; hover it for what it means.'}));
    // What tells the points apart and what they scored first, then the rest in points.csv's order.
    const first = ['index', 'scene', 'preset'].concat(swept, ['on_time', 'fits', 'late_lines', 'fps', 'differing_percent',
                                                               'relmse', 'dsp', 'bram_kbit']);
    const order = first.filter((n, i) => colByName.has(n) && first.indexOf(n) === i).map((n) => colByName.get(n));
    const shown = order.concat(columns.filter((c) => !order.includes(c)));
    const textual = new Set(shown.filter((c) => points.some((p) => typeof p[c.name] === 'string')).map((c) => c.name));
    const heads = shown.map((c) => headerCell(c.name, 'sortable' + (textual.has(c.name) ? ' text' : '')));
    const tbody = el('tbody');
    const rows = points.map((p) => {
      const tr = el('tr', {id: 'point-' + p.index}, shown.map((c) => valueCell(c.name, p[c.name])));
      tr.point = p;
      return tr;
    });
    rows.forEach((r) => tbody.appendChild(r));
    let sortedBy = null, ascending = true;
    heads.forEach((th, n) => th.addEventListener('click', () => {
      const name = shown[n].name;
      ascending = sortedBy === name ? !ascending : true;
      sortedBy = name;
      const rank = (v) => (v === null || v === undefined ? 2 : 0);
      rows.sort((a, b) => {
        const u = a.point[name], v = b.point[name];
        if (rank(u) || rank(v)) return rank(u) - rank(v);  // nulls last either way
        const d = typeof u === 'string' || typeof v === 'string' ? String(u).localeCompare(String(v)) : Number(u) - Number(v);
        return (ascending ? d : -d) || a.point.index - b.point.index;
      });
      rows.forEach((r) => tbody.appendChild(r));
      heads.forEach((h) => h.classList.remove('sorted-asc', 'sorted-desc'));
      th.classList.add(ascending ? 'sorted-asc' : 'sorted-desc');
    }));
    root.appendChild(el('div', {class: 'table-wrap tall'}, [el('table', {}, [el('thead', {}, [el('tr', {}, heads)]), tbody])]));
  }

  // ---- thumbnails ----

  function drawThumbnails() {
    const root = document.getElementById('thumbnails-body');
    const thumbs = arr(data.thumbnails).map(obj).filter((t) => typeof t.src === 'string' && t.src.startsWith('data:image/png;'));
    if (!thumbs.length) {
      root.appendChild(note('No frames kept in this report.'));
      return;
    }
    const box = el('div', {class: 'thumbs'});
    for (const t of thumbs) {
      const img = el('img', {alt: t.caption || ('point ' + t.point)});
      img.src = t.src;
      box.appendChild(el('figure', {class: 'thumb'}, [img, el('figcaption', {}, [isNum(t.point) ? pointLink(t.point) : null, ' ', t.caption || ''])]));
    }
    root.appendChild(box);
  }

  // ---- the self-check ----

  // A canvas has ink when some pixel is neither transparent nor white.
  function inked(canvas) {
    const w = canvas.width, h = canvas.height;
    if (!w || !h) return false;
    const px = canvas.getContext('2d').getImageData(0, 0, w, h).data;
    for (let i = 0; i < px.length; i += 4) {
      if (px[i + 3] !== 0 && (px[i] < 245 || px[i + 1] < 245 || px[i + 2] < 245)) return true;
    }
    return false;
  }

  if (typeof Chart === 'undefined') problems.push('Chart.js did not load');
  else {
    Chart.defaults.font.family = '"DejaVu Sans", "Helvetica Neue", Arial, sans-serif';
    Chart.defaults.color = '#333a47';
  }
  safely('the sweep', drawSweep);
  safely('the cheapest configurations', drawCheapest);
  if (typeof Chart !== 'undefined') safely('the charts', drawCharts);
  safely('the frames', drawThumbnails);
  safely('the table of points', drawPoints);

  let drawn = 0;
  for (const c of charts) {
    try {
      if (inked(c.canvas)) drawn++;
    } catch (e) {
      problems.push('checking a chart: ' + e);
    }
  }
  if (problems.length) {
    const box = document.getElementById('problem');
    box.textContent = 'Part of this page failed to draw:\n' + problems.join('\n');
    box.hidden = false;
    body.dataset.error = problems.join('\n');
  }
  body.dataset.chartsExpected = String(charts.length);
  body.dataset.chartsDrawn = String(drawn);
  body.dataset.ready = '1';
})();
