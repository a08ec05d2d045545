// The view in the URL's fragment: analysis, the stored scenario it starts from, scenario patch, the
// stored mill the mill view starts from, the tandem mill's patch (the mill view), options, report mode
// and the units shown (units=plant; SI when absent). A link
// reproduces the view; the fragment never reaches a server log, and the token is never in it.

export function readState(hash = location.hash) {
  const params = new URLSearchParams(hash.replace(/^#/, ''));
  const json = (name) => {
    try { return params.has(name) ? JSON.parse(params.get(name)) : {}; } catch { return {}; }
  };
  return { analysis: params.get('analysis'), base: params.get('base') || '', millBase: params.get('mill_base') || '', scenario: json('scenario'), tandem: json('tandem'), options: json('options'), view: params.get('view'), units: params.get('units') === 'plant' ? 'plant' : 'si' };
}

export function writeState({ analysis, base, millBase, scenario, tandem = {}, options, view, units }) {
  const params = new URLSearchParams();
  params.set('analysis', analysis);
  if (base) params.set('base', base);
  if (millBase) params.set('mill_base', millBase);
  if (Object.keys(scenario).length) params.set('scenario', JSON.stringify(scenario));
  if (Object.keys(tandem).length) params.set('tandem', JSON.stringify(tandem));
  if (Object.keys(options).length) params.set('options', JSON.stringify(options));
  if (view) params.set('view', view);
  if (units === 'plant') params.set('units', 'plant');
  history.replaceState(null, '', `#${params}`);
  return location.href;
}
