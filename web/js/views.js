// What each analysis draws and lists. Every view takes the service's answer as it is (the
// numbers are plotted unchanged) and returns its headline rows; `csv` gives the tabular part.
import { addPlot, color, line, marker, points } from './charts.js';

const fmt = (value, digits = 4) => {
  if (value === null || value === undefined) return '—';
  if (typeof value !== 'number') return String(value);
  return Math.abs(value) >= 1e5 || (Math.abs(value) < 1e-3 && value !== 0) ? value.toExponential(3) : Number(value.toPrecision(digits)).toString();
};
const row = (label, value, unit = '') => [label, fmt(value), unit];
const max = (values) => Math.max(...values.filter((v) => v !== null));
const min = (values) => Math.min(...values.filter((v) => v !== null));

// Columnar arrays (the bite distribution, time series) as CSV rows.
function columns(object) {
  const keys = Object.keys(object).filter((k) => Array.isArray(object[k]));
  const length = Math.max(0, ...keys.map((k) => object[k].length));
  const rows = [keys];
  for (let i = 0; i < length; i++) rows.push(keys.map((k) => object[k][i]));
  return rows;
}
// An array of flat objects as CSV rows (nested members left out).
function records(list) {
  const keys = [...new Set(list.flatMap((item) => Object.keys(item).filter((k) => typeof item[k] !== 'object' || item[k] === null)))];
  return [keys, ...list.map((item) => keys.map((k) => item[k]))];
}

function drawBite(plots, result, rollSpeed, prefix = '') {
  const d = result.distribution;
  if (!d) return;
  const x = d.x_mm;
  const peak = max(d.pressure_MPa);
  const regimes = [...new Set(d.regime)];
  const shading = regimes.map((regime, i) => ({
    label: `regime: ${regime}`,
    data: points(x, d.regime.map((r) => (r === regime ? peak * 1.05 : null))),
    fill: 'origin', borderWidth: 0, backgroundColor: ['rgba(31,95,168,0.08)', 'rgba(192,57,43,0.10)', 'rgba(46,139,87,0.10)', 'rgba(142,68,173,0.10)'][i % 4],
    pointRadius: 0, order: 10,
  }));
  addPlot(plots, {
    id: `${prefix}pressure`, title: 'Pressure and friction stress along the bite',
    description: 'x is the distance from the exit; the dashed line is the neutral point; shaded: lubrication regime',
    x: 'x from the exit [mm]', y: 'stress [MPa]',
    data: { datasets: [
      line('pressure [MPa]', points(x, d.pressure_MPa), 0),
      line('friction stress [MPa]', points(x, d.friction_MPa), 1),
      marker('neutral point', result.neutral_point_mm, 0, peak, '#333'),
      ...shading,
    ] },
  });
  addPlot(plots, {
    id: `${prefix}film`, title: 'Film thickness and contact ratio',
    x: 'x from the exit [mm]', y: 'film [µm]', y2: 'contact ratio [-]',
    data: { datasets: [
      line('film thickness [µm]', points(x, d.film_um), 2),
      line('contact ratio [-]', points(x, d.contact_ratio), 3, { yAxisID: 'y2' }),
    ] },
  });
  addPlot(plots, {
    id: `${prefix}speed`, title: 'Strip speed and roll speed',
    x: 'x from the exit [mm]', y: 'speed [m/s]',
    data: { datasets: [
      line('strip speed [m/s]', points(x, d.strip_speed_m_per_s), 4),
      line('roll speed [m/s]', [{ x: min(x), y: rollSpeed }, { x: max(x), y: rollSpeed }], 6, { borderDash: [4, 3] }),
      marker('neutral point', result.neutral_point_mm, min(d.strip_speed_m_per_s), max(d.strip_speed_m_per_s), '#333'),
    ] },
  });
}

function biteHeadline(r) {
  return [
    row('status', r.status), row('roll force', r.force_kN, 'kN'), row('roll torque', r.torque_kN_m, 'kN·m'),
    row('forward slip', r.forward_slip, '-'), row('mean friction coefficient', r.mean_friction_coefficient, '-'),
    row('inlet film', r.inlet_film_um, 'µm'), row('neutral point (from exit)', r.neutral_point_mm, 'mm'),
    row('contact length', r.contact_length_mm, 'mm'),
  ];
}

function modeShape(plots, mode, title) {
  if (!mode || !mode.shape) return;
  addPlot(plots, {
    id: 'mode-shape', type: 'bar', title, x: 'mass of the stack (m1 top backup … m6 bottom backup)', y: 'relative amplitude',
    data: { labels: mode.shape.map((_, i) => `m${i + 1}`), datasets: [{ label: `${fmt(mode.frequency_Hz)} Hz`, data: mode.shape, backgroundColor: color(1) }] },
  });
}

function drawCritical(plots, critical) {
  if (!critical) return;
  const speed = critical.critical_speed_m_per_s;
  const branches = critical.damping_branches || [];
  const all = branches.flatMap((b) => b.damping_ratio);
  addPlot(plots, {
    id: 'damping', title: 'Damping ratio of each mode branch over rolling speed',
    description: 'below zero the mode grows: chatter; the dashed line is the critical speed',
    x: 'rolling speed [m/s]', y: 'damping ratio [-]',
    data: { datasets: [
      ...branches.map((b, i) => line(`mode ${i + 1} (${fmt(b.frequency_Hz[0], 3)} Hz at ${fmt(b.speed_m_per_s[0], 3)} m/s)`, points(b.speed_m_per_s, b.damping_ratio), i)),
      ...(speed != null && all.length ? [marker('critical speed', speed, min(all), max(all), '#000')] : []),
    ] },
  });
  const scan = critical.scan || [];
  const growth = scan.map((s) => s.max_growth_rate_per_s);
  addPlot(plots, {
    id: 'growth', title: 'Largest growth rate over rolling speed', x: 'rolling speed [m/s]', y: 'growth rate [1/s]',
    data: { datasets: [
      line('max growth rate [1/s]', points(scan.map((s) => s.speed_m_per_s), growth), 1),
      ...(speed != null && growth.length ? [marker('critical speed', speed, min(growth), max(growth), '#000')] : []),
    ] },
  });
}

export const analyses = [
  {
    key: 'roll_gap', label: 'Roll gap', path: '/v1/roll-gap',
    render(response, plots) {
      const r = response.result;
      drawBite(plots, r, response.scenario.rolls.speed_m_per_s);
      return biteHeadline(r);
    },
    csv: (response) => (response.result.distribution ? columns(response.result.distribution) : records([response.result])),
  },
  {
    key: 'stability', label: 'Stability', path: '/v1/stability',
    render(response, plots) {
      const r = response.result;
      const c = r.critical_speed || {};
      drawCritical(plots, r.critical_speed);
      const mode = c.unstable_mode || r.least_damped_mode;
      modeShape(plots, mode, c.unstable_mode ? 'Shape of the mode that turns unstable' : 'Shape of the least-damped mode');
      return [
        row('stable at the scenario speed', r.stable), row('rolling speed', r.speed_m_per_s, 'm/s'),
        row('critical speed', c.critical_speed_m_per_s, 'm/s'), row('search status', c.status),
        row('unstable mode frequency', c.unstable_mode && c.unstable_mode.frequency_Hz, 'Hz'),
        row('least-damped mode', r.least_damped_mode && r.least_damped_mode.frequency_Hz, 'Hz'),
        row('its damping ratio', r.least_damped_mode && r.least_damped_mode.damping_ratio, '-'),
        row('strip stiffness', r.strip_stiffness_GN_per_m, 'GN/m'),
      ];
    },
    csv: (response) => records((response.result.critical_speed || {}).scan || []),
  },
  {
    key: 'amplitude', label: 'Amplitude', path: '/v1/amplitude',
    render(response, plots) {
      const p = response.result.points;
      const v = p.map((q) => q.speed_m_per_s);
      addPlot(plots, {
        id: 'amplitude', title: 'Vibration amplitude over rolling speed', x: 'rolling speed [m/s]', y: 'amplitude [µm]', y2: 'force amplitude [kN]',
        data: { datasets: [
          line('gap amplitude [µm]', points(v, p.map((q) => q.gap_amplitude_um)), 0, { pointRadius: 4 }),
          line('upper roll amplitude [µm]', points(v, p.map((q) => q.upper_roll_amplitude_um)), 1, { pointRadius: 4 }),
          line('force amplitude [kN]', points(v, p.map((q) => q.force_amplitude_kN)), 2, { pointRadius: 4, yAxisID: 'y2' }),
        ] },
      });
      p.filter((q) => q.time_series).forEach((q, i) => addPlot(plots, {
        id: `series-${i}`, title: `Time series at ${fmt(q.speed_m_per_s)} m/s`, x: 'time [s]', y: 'gap [µm]', y2: 'force [kN]',
        data: { datasets: [
          line('gap [µm]', points(q.time_series.t_s, q.time_series.gap_um), 0),
          line('force [kN]', points(q.time_series.t_s, q.time_series.force_kN), 2, { yAxisID: 'y2' }),
        ] },
      }));
      return p.map((q) => row(`gap amplitude at ${fmt(q.speed_m_per_s)} m/s (${q.status})`, q.gap_amplitude_um, 'µm'));
    },
    csv: (response) => records(response.result.points),
  },
  {
    key: 'tension_cycle', label: 'Tension cycle', path: '/v1/tension-cycle',
    render(response, plots) {
      const r = response.result;
      r.phases.forEach((phase, i) => {
        if (i === 0) drawBite(plots, phase.roll_gap, response.scenario.rolls.speed_m_per_s, `phase${i}-`);
      });
      const withDistribution = r.phases.filter((p) => p.roll_gap.distribution);
      if (withDistribution.length) {
        addPlot(plots, {
          id: 'phases', title: 'Pressure along the bite at each phase of the back tension', x: 'x from the exit [mm]', y: 'pressure [MPa]',
          data: { datasets: withDistribution.map((p, i) => line(`phase ${p.phase} (back tension ${fmt(p.back_tension_MPa)} MPa)`, points(p.roll_gap.distribution.x_mm, p.roll_gap.distribution.pressure_MPa), i)) },
        });
      }
      return [row('status', r.status), ...r.phases.map((p) => row(`force at phase ${p.phase} (back tension ${fmt(p.back_tension_MPa)} MPa)`, p.roll_gap.force_kN, 'kN'))];
    },
    csv: (response) => records(response.result.phases.map((p) => ({ ...p, ...p.roll_gap }))),
  },
  {
    key: 'sweep', label: 'Sweep', path: '/v1/sweeps', job: true,
    render(response, plots) {
      const r = response.result;
      const critical = r.quantity !== 'amplitude';
      const unit = r.unit && r.unit !== '1' ? ` [${r.unit}]` : '';
      const v = r.points.map((p) => p.value);
      addPlot(plots, {
        id: 'sweep', title: `${critical ? 'Critical speed' : 'Amplitude'} over ${r.parameter}`, x: `${r.parameter}${unit}`,
        y: critical ? 'critical speed [m/s]' : 'gap amplitude [µm]', y2: critical ? 'chatter frequency [Hz]' : undefined,
        data: { datasets: critical ? [
          line('critical speed [m/s]', points(v, r.points.map((p) => p.critical_speed_m_per_s)), 0, { pointRadius: 3 }),
          line('frequency of the unstable mode [Hz]', points(v, r.points.map((p) => p.frequency_Hz)), 1, { pointRadius: 3, yAxisID: 'y2' }),
        ] : [line('gap amplitude [µm]', points(v, r.points.map((p) => p.gap_amplitude_um)), 0, { pointRadius: 3 })] },
      });
      return [row('parameter', r.parameter), row('values', r.points.length), row('quantity', r.quantity)];
    },
    csv: (response) => records(response.result.points),
  },
];

export const analysisByKey = (key) => analyses.find((a) => a.key === key) || analyses[0];
export { fmt };
