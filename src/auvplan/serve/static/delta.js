// auvplan serve: the page's copy of the server's waypoints and violations, kept by the answers' splices.
// The rule (the same as auvplan.serve.delta.take, in Python): a splice names the revision it applies to
// (`base`) and the one it makes (`rev`); it is applied only on exactly that base; an answer older than
// the copy is dropped whole; anything else empties the copy and the page asks for the whole state.
"use strict";
function takeState(copy, st) {  // copy = {rev, w, v}; returns "ok", "stale" or "gap"
  const rev = st.rev === undefined ? null : st.rev;
  if (copy.rev !== null && rev !== null && rev < copy.rev) return "stale";
  const d = st.delta;
  if (d && rev !== null && copy.rev !== null && d.base === copy.rev) {
    const v = d.violations;
    if (d.waypoints.length || d.stop > d.start) copy.w.splice(d.start, d.stop - d.start, ...d.waypoints.map((p) => p.slice()));
    if (v.items.length || v.stop > v.start) copy.v.splice(v.start, v.stop - v.start, ...v.items);
  } else if (!d && st.waypoints) {
    copy.w = st.waypoints.map((p) => p.slice());
    copy.v = (st.check && st.check.violations) || [];
  } else {
    copy.rev = null; return "gap";
  }
  copy.rev = rev;
  return "ok";
}
if (typeof module !== "undefined") module.exports = { takeState };
