// rbShared(key, missing): the page of an inline view (viewer/sharing.py) takes meshcat's script from the notebook's
// page, its parent, which answers a postMessage with it; the page's scripts held back (type %AFTER%) then run.
function rbShared(key, missing) {
  // an inline view's page (sharing.py): meshcat's script comes from the notebook's page (postMessage to the
  // parent); then the page's held scripts run, in order.  No answer in 5 s: say so (missing), and keep asking.
  var done = false, tries = 0, note = null;
  function ask() {
    if (done) return;
    try { window.parent.postMessage({rbcourseMeshcat: "want", key: key}, "*"); } catch (e) {}
    if (++tries === 20) {
      note = document.createElement("div");
      note.id = "rb-missing";
      note.style.cssText = "position: fixed; left: 12px; right: 12px; top: 12px; z-index: 20; padding: 10px 12px; " +
        "font: bold 15px/1.4 sans-serif; color: #fff; background: rgba(160, 20, 20, 0.9); border-radius: 4px";
      note.textContent = missing;
      document.body.appendChild(note);
    }
    setTimeout(ask, tries < 20 ? 250 : 2000);
  }
  function start(d) {
    rbScript(d.text, d.size);
    var held = document.querySelectorAll('script[type="%AFTER%"]');
    for (var i = 0; i < held.length; i++) {
      var s = document.createElement("script");
      s.text = held[i].text;
      held[i].parentNode.replaceChild(s, held[i]);
    }
  }
  window.addEventListener("message", function (e) {
    var d = e.data;
    if (done || !d || d.rbcourseMeshcat !== "script" || d.key !== key) return;
    done = true;
    if (note) note.remove();
    if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", function () { start(d); });
    else start(d);
  });
  ask();
}
