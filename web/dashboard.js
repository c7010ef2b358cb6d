// m2mlat's live dashboard: reads the snapshot (format m2mlat-live/1, docs/dashboard.md) once from
// api/live, then follows api/live/stream (server-sent events) and redraws the numbers, the strip
// chart and the histogram (inline SVG) and the agents' table on every snapshot. No framework, nothing
// from the network. Times arrive as int64 ns; JavaScript numbers keep them to within a microsecond,
// which is plenty for drawing. A `token` in this page's URL is passed on to the API (the dashboard
// needs one when it listens on a non-loopback address).
'use strict';

(function () {
  const SVG_NS = 'http://www.w3.org/2000/svg';
  const token = new URLSearchParams(window.location.search).get('token');
  const query = token ? '?token=' + encodeURIComponent(token) : '';
  const $ = (id) => document.getElementById(id);

  // ---- formatting --------------------------------------------------------------------------
  const fmtMs = (ms, digits = 1) => (ms === null || ms === undefined || !isFinite(ms) ? '-' : ms.toFixed(digits) + ' ms');
  const nsToMs = (ns) => ns / 1e6;
  const fmtCount = (n) => (n === null || n === undefined ? '-' : String(n));
  function fmtAge(ns) {
    if (ns < 0) return 'just now';
    const s = ns / 1e9;
    if (s < 60) return s.toFixed(1) + ' s ago';
    if (s < 3600) return (s / 60).toFixed(1) + ' min ago';
    return (s / 3600).toFixed(1) + ' h ago';
  }
  function setText(id, text) {
    const el = $(id);
    if (el.textContent !== text) el.textContent = text;
  }

  // ---- SVG helpers -------------------------------------------------------------------------
  function el(name, attrs, text) {
    const node = document.createElementNS(SVG_NS, name);
    for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, String(v));
    if (text !== undefined) node.textContent = text;
    return node;
  }
  // About `count` round tick values (1, 2, 5 x 10^k steps) covering [lo, hi].
  function ticks(lo, hi, count) {
    if (!(hi > lo)) return [lo];
    const raw = (hi - lo) / count;
    const mag = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw);
    const out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(+v.toFixed(10));
    return out;
  }
  const frame = { left: 52, right: 12, top: 10, bottom: 30 };
  // Both axes carry their quantity and unit: xLabel under the x axis' right end, yLabel turned
  // along the y axis.
  function axes(svg, w, h, xTicks, yTicks, xs, ys, xLabel, yLabel) {
    for (const t of yTicks) {
      svg.appendChild(el('line', { class: 'grid', x1: frame.left, x2: w - frame.right, y1: ys(t), y2: ys(t) }));
      svg.appendChild(el('text', { class: 'tick', x: frame.left - 6, y: ys(t) + 4, 'text-anchor': 'end' }, String(t)));
    }
    for (const t of xTicks)
      svg.appendChild(el('text', { class: 'tick', x: xs(t), y: h - frame.bottom + 16, 'text-anchor': 'middle' }, String(t)));
    svg.appendChild(el('line', { class: 'axis', x1: frame.left, x2: frame.left, y1: frame.top, y2: h - frame.bottom }));
    svg.appendChild(el('line', { class: 'axis', x1: frame.left, x2: w - frame.right, y1: h - frame.bottom, y2: h - frame.bottom }));
    svg.appendChild(el('text', { class: 'tick axis-label', x: w - frame.right, y: h - 2, 'text-anchor': 'end' }, xLabel));
    const yMid = (frame.top + h - frame.bottom) / 2;
    svg.appendChild(el('text', { class: 'tick axis-label', x: 12, y: yMid, 'text-anchor': 'middle',
      transform: `rotate(-90 12 ${yMid})` }, yLabel));
  }
  function clear(svg) {
    while (svg.firstChild) svg.removeChild(svg.firstChild);
  }
  function empty(svg, w, h, text) {
    svg.appendChild(el('text', { class: 'empty', x: w / 2, y: h / 2, 'text-anchor': 'middle' }, text));
  }

  // ---- strip chart: latency (ms) against the cause edge's time, seconds before the newest -----
  function drawStrip(snap) {
    const svg = $('strip');
    const [w, h] = [640, 260];
    clear(svg);
    const recent = snap.recent || [];
    if (recent.length === 0) return empty(svg, w, h, 'no pairs yet');
    const newest = recent[recent.length - 1].t_ns;
    const pts = recent.map((p) => ({ x: (p.t_ns - newest) / 1e9, y: nsToMs(p.latency_ns), ambiguous: p.ambiguous }));
    const s = snap.summary;
    let yLo = Math.min(...pts.map((p) => p.y));
    let yHi = Math.max(...pts.map((p) => p.y));
    if (s.q1_ms !== null) yLo = Math.min(yLo, s.q1_ms);
    if (s.q3_ms !== null) yHi = Math.max(yHi, s.q3_ms);
    const pad = Math.max((yHi - yLo) * 0.08, 1);
    yLo -= pad;
    yHi += pad;
    const xLo = Math.min(pts[0].x, -1);
    const xs = (x) => frame.left + ((x - xLo) / (0 - xLo)) * (w - frame.left - frame.right);
    const ys = (y) => h - frame.bottom - ((y - yLo) / (yHi - yLo)) * (h - frame.top - frame.bottom);
    if (s.q1_ms !== null && s.q3_ms !== null)
      svg.appendChild(el('rect', { class: 'band', x: frame.left, width: w - frame.left - frame.right,
        y: ys(s.q3_ms), height: Math.max(ys(s.q1_ms) - ys(s.q3_ms), 0) }));
    axes(svg, w, h, ticks(xLo, 0, 6), ticks(yLo, yHi, 5), xs, ys, 'time (s before the newest pair)', 'latency (ms)');
    if (s.median_ms !== null)
      svg.appendChild(el('line', { class: 'median', x1: frame.left, x2: w - frame.right, y1: ys(s.median_ms), y2: ys(s.median_ms) }));
    for (const p of pts)
      svg.appendChild(el('circle', { class: p.ambiguous ? 'point ambiguous' : 'point', cx: xs(p.x), cy: ys(p.y), r: 2.6 }));
  }

  // ---- histogram ---------------------------------------------------------------------------
  function drawHistogram(snap) {
    const svg = $('histogram');
    const [w, h] = [420, 260];
    clear(svg);
    const hist = snap.histogram || { bins: [], width_ns: 0 };
    if (!hist.bins.length) return empty(svg, w, h, 'no samples yet');
    const width = nsToMs(hist.width_ns);
    const xLo = nsToMs(hist.bins[0].lower_ns);
    const xHi = nsToMs(hist.bins[hist.bins.length - 1].lower_ns) + width;
    const top = Math.max(...hist.bins.map((b) => b.count));
    const xs = (x) => frame.left + ((x - xLo) / (xHi - xLo)) * (w - frame.left - frame.right);
    const ys = (y) => h - frame.bottom - (y / top) * (h - frame.top - frame.bottom);
    axes(svg, w, h, ticks(xLo, xHi, 5), ticks(0, top, 4).filter((t) => Number.isInteger(t)), xs, ys, 'latency (ms)', 'pairs');
    for (const b of hist.bins) {
      if (b.count === 0) continue;
      const x0 = xs(nsToMs(b.lower_ns));
      const x1 = xs(nsToMs(b.lower_ns) + width);
      const bar = el('rect', { class: 'bar', x: x0 + 0.5, width: Math.max(x1 - x0 - 1, 0.5), y: ys(b.count),
        height: ys(0) - ys(b.count) });
      bar.appendChild(el('title', {}, `${nsToMs(b.lower_ns).toFixed(1)} .. ${(nsToMs(b.lower_ns) + width).toFixed(1)} ms: ${b.count}`));
      svg.appendChild(bar);
    }
  }

  // ---- agents' table -----------------------------------------------------------------------
  function drawNodes(snap) {
    const body = $('nodes').tBodies[0];
    const nodes = snap.nodes || [];
    $('agents').hidden = nodes.length === 0;  // `m2mlat watch` has no agents
    const rows = nodes.map((n) => {
      const tr = document.createElement('tr');
      const cell = (text, cls) => {
        const td = document.createElement('td');
        td.textContent = text;
        if (cls) td.className = cls;
        tr.appendChild(td);
        return td;
      };
      cell(n.node || n.url).title = n.url;  // the URL until the agent has answered
      cell(n.role);
      const state = document.createElement('span');
      state.className = 'badge badge-' + n.state;
      state.textContent = n.state;
      cell('').appendChild(state);
      cell(n.events_per_s.toFixed(1), 'num');
      cell(fmtCount(n.events), 'num');
      cell(fmtCount(Math.max(n.agent_last_seq - n.cursor_seq, 0)), 'num');
      cell(fmtCount(n.lost), 'num');
      cell(n.has_clock ? (n.clock_offset_ns >= 0 ? '+' : '') + nsToMs(n.clock_offset_ns).toFixed(3) + ' ms' : '-', 'num');
      cell(n.has_clock ? nsToMs(n.clock_max_error_ns).toFixed(3) + ' ms' : '-', 'num');
      cell(n.has_clock ? (n.synchronised ? 'yes' : 'NO') : '-');
      cell(n.last_contact_ns ? fmtAge(snap.now_ns - n.last_contact_ns) : 'never', 'num');
      cell(n.last_error || '', 'error');
      return tr;
    });
    body.replaceChildren(...rows);
  }

  // ---- the full loop: M2M, G2G, E2E side by side (scenarios with gyroscope traces) -------------
  function drawLoop(s) {
    const loop = s.full_loop;
    $('full-loop').hidden = !loop;
    if (!loop) return;
    setText('loop-window', `(${loop.chains} chains over the last ${(loop.window_ns / 1e9).toFixed(0)} s, ` +
      `${loop.detector} onsets)`);
    for (const q of ['m2m', 'g2g', 'e2e']) {
      const x = loop[q];
      setText(q + '-n', fmtCount(x.n));
      setText(q + '-median', fmtMs(x.median_ms));
      setText(q + '-p95', fmtMs(x.p95_ms));
      setText(q + '-last', x.last_ns === null ? '-' : fmtMs(nsToMs(x.last_ns)));
    }
    const gaps = Object.entries(loop.incomplete_chains).filter(([, n]) => n > 0).map(([k, n]) => `${k} ${n}`);
    setText('loop-incomplete', 'incomplete chains: ' + (gaps.length ? gaps.join(', ') : 'none') +
      (loop.warnings.length ? ' \u00b7 ' + loop.warnings.join('; ') : ''));
  }

  // ---- the stage breakdown (collect --stages): one stacked bar of the stages' means, the table ------
  // Six colours, used in turn (stage-0 .. stage-5 in dashboard.css).
  const stageClass = (k) => 'stage-' + (k % 6);
  function drawBreakdown(s) {
    const b = s.breakdown;
    $('breakdown').hidden = !b;
    if (!b) return;
    setText('breakdown-scenario', s.scenario || '-');
    setText('breakdown-counts', `(${b.complete} complete / ${b.incomplete} incomplete of ${b.events} events)`);
    const svg = $('breakdown-bar');
    const [w, h] = [640, 96];
    const barTop = 14, barHeight = 34;
    clear(svg);
    const total = b.m2m_mean_ms;
    if (b.complete === 0 || total === null || !(total > 0)) {
      empty(svg, w, h, 'no complete chain yet');
    } else {
      const xs = (ms) => frame.left + (ms / total) * (w - frame.left - frame.right);
      let at = 0;
      b.stages.forEach((st, k) => {
        const mean = Math.max(st.mean_ms || 0, 0);
        const x0 = xs(at), x1 = xs(at + mean);
        const rect = el('rect', { class: 'segment ' + stageClass(k), x: x0, y: barTop, width: Math.max(x1 - x0, 0),
          height: barHeight, 'data-stage': st.name });
        rect.appendChild(el('title', {}, `${st.name}: mean ${fmtMs(st.mean_ms, 3)}, median ${fmtMs(st.median_ms, 3)}`));
        svg.appendChild(rect);
        // The stage's name inside its segment when it fits (about 6.5 px a character at 11 px).
        const label = `${st.name} ${fmtMs(st.mean_ms)}`;
        if (x1 - x0 > label.length * 6.5 + 6)
          svg.appendChild(el('text', { class: 'stage-label', x: (x0 + x1) / 2, y: barTop + barHeight / 2 + 4,
            'text-anchor': 'middle' }, label));
        at += mean;
      });
      const xt = ticks(0, total, 5).filter((t) => t <= total);
      for (const t of xt)
        svg.appendChild(el('text', { class: 'tick', x: xs(t), y: barTop + barHeight + 16, 'text-anchor': 'middle' }, String(t)));
      svg.appendChild(el('line', { class: 'axis', x1: frame.left, x2: w - frame.right, y1: barTop + barHeight + 2,
        y2: barTop + barHeight + 2 }));
      svg.appendChild(el('text', { class: 'tick axis-label', x: w - frame.right, y: h - 4, 'text-anchor': 'end' },
        `time from the cause (ms; mean M2M ${fmtMs(total)})`));
    }
    const body = $('stages').tBodies[0];
    while (body.firstChild) body.removeChild(body.firstChild);
    b.stages.forEach((st, k) => {
      const tr = document.createElement('tr');
      const name = document.createElement('td');
      const swatch = document.createElement('span');
      swatch.className = 'swatch ' + stageClass(k);
      name.append(swatch, st.name);
      tr.appendChild(name);
      const cells = [[st.ends_at, ''], [fmtMs(st.median_ms, 3), 'num'], [fmtMs(st.iqr_ms, 3), 'num'],
        [fmtMs(st.mean_ms, 3), 'num'], [st.share === null ? '-' : (st.share * 100).toFixed(1) + ' %', 'num']];
      for (const [text, cls] of cells) {
        const td = document.createElement('td');
        if (cls) td.className = cls;
        td.textContent = text;
        tr.appendChild(td);
      }
      body.appendChild(tr);
    });
    const gaps = b.incomplete_by_reason.map((g) => `${g.count} ${g.reason} at ${g.stage}`);
    setText('breakdown-incomplete', 'incomplete chains: ' + (gaps.length ? gaps.join(', ') : 'none') +
      ` · M2M median ${fmtMs(b.m2m_median_ms, 3)} over the complete events`);
  }

  // ---- boards down: the red banner at the top and the badge -------------------------------------
  // A board stale or unreachable is named at the top at once (the table below says more); the badge
  // then turns red too, whatever the state of the page's own link to the coordinator.
  let stream = { state: 'waiting', text: 'connecting' };  // the page's link to the coordinator
  let down = [];                                           // "node state" of each board not ok
  function drawAlert(snap) {
    const bad = (snap.nodes || []).filter((n) => n.state !== 'ok');
    down = bad.map((n) => `${n.node || n.url} ${n.state}`);
    const alert = $('alert');
    alert.hidden = bad.length === 0;
    setText('alert', bad.map((n) => {
      const since = n.last_contact_ns ? 'last contact ' + fmtAge(snap.now_ns - n.last_contact_ns) : 'never answered';
      return `${n.node || n.url} ${n.state.toUpperCase()} (${since}${n.last_error ? ': ' + n.last_error : ''})`;
    }).join(' \u00b7 '));
    drawConnection();
  }
  function drawConnection() {
    const badge = $('connection');
    const bad = stream.state === 'ok' && down.length > 0;
    badge.className = 'badge badge-' + (bad ? 'error' : stream.state);
    badge.textContent = bad ? `${stream.text} \u00b7 ${down.length} board${down.length > 1 ? 's' : ''} down` : stream.text;
  }

  // ---- the whole page ----------------------------------------------------------------------
  function apply(snap) {
    const s = snap.summary;
    setText('scenario', s.scenario ? `${s.scenario}: ${s.cause || '?'} \u2192 ${s.effect || '?'}` : '-');
    // Not ok: why; ok: the sanity verdict's warnings (roles that look swapped, no pairs), if any.
    const message = $('message');
    const warnings = s.warnings || [];
    message.hidden = s.state === 'ok' ? !warnings.length : !s.message;
    setText('message', s.state === 'ok' ? warnings.map((w) => 'warning: ' + w).join(' \u00b7 ') : `${s.state}: ${s.message}`);
    setText('samples', fmtCount(s.samples));
    setText('last', s.last ? fmtMs(nsToMs(s.last.latency_ns)) : '-');
    setText('median', fmtMs(s.median_ms));
    setText('iqr', fmtMs(s.iqr_ms));
    setText('quartiles', s.q1_ms === null ? '-' : `Q1 ${fmtMs(s.q1_ms)} .. Q3 ${fmtMs(s.q3_ms)}`);
    // The bootstrap's interval (the level, e.g. 95 %, and its ends), as `m2mlat stats` gives it.
    const fmtCi = (ci) => (ci ? `${Math.round(s.ci_level * 100)} % CI ${ci[0].toFixed(1)} .. ${ci[1].toFixed(1)} ms` : '-');
    setText('median-ci', fmtCi(s.median_ci_ms));
    setText('iqr-ci', fmtCi(s.iqr_ci_ms));
    setText('p95', fmtMs(s.p95_ms));
    setText('pairs', fmtCount(s.pairs));
    setText('ambiguous', `${s.ambiguous} ambiguous`);
    setText('unmatched', `${s.cause_unmatched} / ${s.effect_unmatched}`);
    setText('bounces', `${s.bounces} bounces; edges ${s.cause_events} / ${s.effect_events}`);
    drawLoop(s);
    drawBreakdown(s);
    drawStrip(snap);
    drawHistogram(snap);
    drawNodes(snap);
    drawAlert(snap);
    setText('footer', `updated ${new Date(snap.now_ns / 1e6).toISOString()} \u00b7 ${s.pairings} pairings, ` +
      `last took ${(s.update_cost_ns / 1e6).toFixed(1)} ms \u00b7 store seq ${s.store_last_seq}`);
  }

  function connection(state, text) {
    stream = { state, text };
    drawConnection();
  }

  function start() {
    fetch('api/live' + query, { cache: 'no-store' })
      .then((r) => (r.ok ? r.json() : Promise.reject(new Error('HTTP ' + r.status))))
      .then((snap) => { if (snap.summary) apply(snap); })
      .catch((e) => connection('error', 'no data: ' + e.message));
    const stream = new EventSource('api/live/stream' + query);
    stream.addEventListener('snapshot', (e) => {
      connection('ok', 'live');
      apply(JSON.parse(e.data));
    });
    stream.addEventListener('open', () => connection('ok', 'live'));
    // EventSource reconnects by itself; say so meanwhile.
    stream.addEventListener('error', () => connection('waiting', 'reconnecting'));
  }

  start();
})();
