// catrt console: live updates. The server sends the journal's last sequence number
// (server-sent events, /events); when it moves past the one this page was built at,
// the page is built again. No library, nothing fetched from elsewhere.
(function () {
  "use strict";
  var body = document.body;
  var shown = body.getAttribute("data-seq");
  var badge = document.getElementById("live");
  if (shown === null || !window.EventSource) { return; }
  var source = new EventSource("/events");
  source.addEventListener("open", function () { if (badge) { badge.textContent = "live"; } });
  source.addEventListener("error", function () { if (badge) { badge.textContent = "offline"; } });
  source.addEventListener("seq", function (e) {
    if (e.data !== shown) { source.close(); window.location.reload(); }
  });
})();
