(function () {
  "use strict";
  var reopen = [];
  window.addEventListener("beforeprint", function () {
    reopen = [];
    document.querySelectorAll("details:not([open])").forEach(function (d) {
      d.open = true;
      reopen.push(d);
    });
  });
  window.addEventListener("afterprint", function () {
    reopen.forEach(function (d) { d.open = false; });
    reopen = [];
  });
  document.querySelectorAll("[data-links]").forEach(function (button) {
    button.hidden = false;
    button.addEventListener("click", function () {
      var open = button.getAttribute("data-links") === "open";
      document.querySelectorAll("details.link").forEach(function (d) { d.open = open; });
    });
  });
  function reveal() {
    var id = decodeURIComponent(window.location.hash.slice(1));
    var target = id ? document.getElementById(id) : null;
    if (target && target.tagName === "DETAILS") { target.open = true; }
  }
  window.addEventListener("hashchange", reveal);
  reveal();
  var readout = document.getElementById("matrix-readout");
  var grid = document.querySelector("svg.matrix");
  if (readout && grid) {
    var lit = [];
    grid.addEventListener("mouseover", function (event) {
      var cell = event.target;
      var tip = cell.tagName === "rect" ? cell.querySelector("title") : null;
      if (!tip) { return; }
      readout.textContent = tip.textContent;
      lit.forEach(function (label) { label.classList.remove("lit"); });
      lit = [
        grid.querySelector('text.row[data-i="' + cell.getAttribute("data-row") + '"]'),
        grid.querySelector('text.col[data-i="' + cell.getAttribute("data-col") + '"]')
      ].filter(Boolean);
      lit.forEach(function (label) { label.classList.add("lit"); });
    });
  }
})();
