// sar-tree studio: the replay's event list. Every event of the recording in order (the
// "events" of the replay's hello), each row a link to its instant: a click moves the
// timeline there, and the tree, blackboard, map and reasons follow. The row of the instant
// shown is marked while playing or scrubbing. The rows are built once per hello; an instant
// costs a bisection of their times and at most two class changes, whatever their number,
// and the list scrolls to the marked row at most once per drawn frame.
// The address keeps the last instant linked to (#t=...); opening such an address, or
// changing it to one, goes there.
"use strict";

const eventList = {
  times: new Float64Array(0),  // each row's instant, in order
  rows: [],                    // each row's <li>
  now: -1,                     // the row marked as the instant shown
  clicked: -1,                 // the row last clicked (marked among rows of the same instant)
};
window.eventList = eventList;  // the browser tests read it

function eventPart(tag, cls, text) {
  const part = document.createElement(tag);
  part.className = cls;
  part.textContent = text;
  return part;
}

function eventRow(e, start) {
  const li = document.createElement("li");
  li.className = `${e.kind} mark-${e.mark}`;
  li.dataset.i = e.i;
  li.dataset.kind = e.kind;
  li.dataset.t = e.t;
  const link = document.createElement("a");
  link.href = `#t=${e.t}`;
  link.title = `${e.kind} #${e.seq} @ ${(e.t - start).toFixed(2)} s: ${e.message}`;
  const who = [e.node, ...e.fields, e.status].filter(Boolean).join(" · ");
  link.append(eventPart("span", "time", (e.t - start).toFixed(1)), " ",
              eventPart("b", "kind", e.kind), " ", eventPart("span", "who", who), " ",
              eventPart("span", "msg", e.message));
  li.appendChild(link);
  return li;
}

// The list of a replay's events (hello.timeline.events); start: the timeline's first instant.
function fillEvents(events, start) {
  const list = document.getElementById("events");
  const pick = document.getElementById("event-kind");
  document.getElementById("events-box").hidden = false;
  eventList.times = Float64Array.from(events, (e) => e.t);
  eventList.rows = events.map((e) => eventRow(e, start));
  eventList.now = -1;
  eventList.clicked = -1;
  list.replaceChildren(...eventList.rows);
  const counts = new Map();
  for (const e of events) counts.set(e.kind, (counts.get(e.kind) || 0) + 1);
  pick.replaceChildren(new Option(`all ${events.length}`, ""));
  for (const [kind, n] of counts) pick.appendChild(new Option(`${kind} ${n}`, kind));
  pick.onchange = () => showKind(pick.value);
  list.onclick = (click) => {
    const li = click.target.closest("li");
    if (!li) return;
    click.preventDefault();
    goToEvent(Number(li.dataset.i));
  };
  seekLinked();
}

function seekLinked() {  // the instant the address names (#t=...), if any
  const linked = /^#t=([-+0-9.eE]+)$/.exec(location.hash);
  const t = linked ? parseFloat(linked[1]) : NaN;
  if (!Number.isFinite(t) || !eventList.rows.length) return;
  pause();
  seek(t);
}
window.addEventListener("hashchange", seekLinked);

function goToEvent(i) {
  const t = eventList.times[i];
  eventList.clicked = i;
  history.replaceState(null, "", `#t=${t}`);
  pause();
  seek(t);
  showEventAt(t);
}

function showKind(kind) {  // "" shows every kind
  for (const li of eventList.rows) li.hidden = kind !== "" && li.dataset.kind !== kind;
  if (eventList.now >= 0) scrollToRow(eventList.rows[eventList.now]);
}

// Mark the row of instant t: the last event at or before it (the clicked one among equals).
function showEventAt(t) {
  const times = eventList.times;
  let lo = 0;
  let hi = times.length;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (times[mid] <= t) lo = mid + 1;
    else hi = mid;
  }
  const c = eventList.clicked;
  const i = c >= 0 && times[c] === t ? c : lo - 1;
  if (i === eventList.now) return;
  if (eventList.now >= 0) eventList.rows[eventList.now].classList.remove("now");
  eventList.now = i;
  if (i < 0) return;
  eventList.rows[i].classList.add("now");
  scrollToRow(eventList.rows[i]);
}

// Scroll the list to a row once the page draws next (at most one layout read per drawn frame,
// however many instants are shown in between), unless the pointer is in the list.
let rowToScroll = null;
function scrollToRow(row) {
  if (rowToScroll === null) requestAnimationFrame(scrollNow);
  rowToScroll = row;
}

function scrollNow() {
  const row = rowToScroll;
  rowToScroll = null;
  const list = document.getElementById("events");
  if (row.hidden || list.matches(":hover")) return;
  const top = row.offsetTop;
  if (top < list.scrollTop || top + row.offsetHeight > list.scrollTop + list.clientHeight) {
    list.scrollTop = Math.max(0, top - list.clientHeight / 2);
  }
}
