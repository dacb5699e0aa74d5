// Text for the web view's tables: ages in seconds, minutes or hours, and values escaped for HTML.
'use strict';

(() => {
  // An age in seconds as "4.2 s", "12 s", "3 m 05 s" or "1 h 02 m"; "–" when unknown.
  function fmtAge(s) {
    if (s === undefined || s === null || !isFinite(s)) return '–';
    s = Math.max(0, s);
    if (s < 60) return `${s.toFixed(s < 10 ? 1 : 0)} s`;
    const m = Math.floor(s / 60);
    if (m < 60) return `${m} m ${String(Math.floor(s % 60)).padStart(2, '0')} s`;
    return `${Math.floor(m / 60)} h ${String(m % 60).padStart(2, '0')} m`;
  }

  // A value as HTML text.
  const esc = (v) => String(v ?? '').replace(/[&<>"']/g, (ch) => `&#${ch.charCodeAt(0)};`);

  const api = { fmtAge, esc };
  if (typeof module !== 'undefined' && module.exports) module.exports = api;
  else globalThis.fleetText = api;
})();
