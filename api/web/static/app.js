// The geomcheck page: upload a description, follow its check, read and download the report.
// Plain JavaScript on the public HTTP API only (POST/GET/DELETE /v1/checks...), so the page
// behaves the same whichever mode runs the checks. Untrusted text is only ever set as
// textContent; the HTML report is shown in a sandboxed frame without same-origin access.
"use strict";

(() => {
  const body = document.body;
  const base = body.dataset.base || "";
  const maxBodyBytes = Number(body.dataset.maxBodyBytes);
  const maxFiles = Number(body.dataset.maxFiles);
  const TOKEN_KEY = "geomcheck.token";
  const ARCHIVE = /\.(zip|tar|tgz|tar\.gz)$/i;
  // what finding the root reads: the descriptions, and the files that may name one (launch
  // files, documentation, model.config, SRDF); never the meshes
  const DESCRIPTION = /(\.(urdf|xacro|sdf|xml|launch|py|md|rst|txt|ya?ml|config|srdf))$/i;
  const RUNNING = new Set(["queued", "running"]);
  const POLL_MS = 1000;
  const CLOCK_SLACK_MS = 2000;
  const $ = (id) => document.getElementById(id);

  const state = {
    upload: null, // {kind: "folder" | "archive" | "file", files: [{path, file}], label}
    checkId: null,
    check: null,
    clockOffset: 0, // server clock minus browser clock [ms]
    pollTimer: null,
    retries: [], // what to run again once a token is given
    cursors: [null], // cursor of each recent-checks page seen so far
    page: 0,
    nextCursor: null,
    chosen: null, // the root the service would take ({path, reason}), null when it would not guess
    undecided: null, // why it would not: several robots equally likely
  };

  class ApiError extends Error {
    constructor(status, detail) {
      super(detail);
      this.status = status;
    }
  }

  // ---- the API ----

  function token() {
    return sessionStorage.getItem(TOKEN_KEY) || "";
  }

  async function api(path, init = {}) {
    const headers = new Headers(init.headers || {});
    if (token()) headers.set("Authorization", `Bearer ${token()}`);
    const response = await fetch(base + path, { ...init, headers });
    // the Date header has whole seconds: trusted over the browser's clock only when they differ more
    const date = Date.parse(response.headers.get("Date") || "");
    if (!Number.isNaN(date)) state.clockOffset = Math.abs(date - Date.now()) > CLOCK_SLACK_MS ? date - Date.now() : 0;
    if (!response.ok) throw new ApiError(response.status, await detailOf(response));
    return response;
  }

  async function detailOf(response) {
    const text = await response.text();
    try {
      const detail = JSON.parse(text).detail;
      if (typeof detail === "string") return detail;
    } catch (err) {
      // not JSON: a proxy's page, say; its status is all there is
    }
    return `HTTP ${response.status} ${response.statusText}`.trim();
  }

  // run `action`; when the service asks for a token, ask the person and run it again once given
  async function guarded(action) {
    try {
      return await action();
    } catch (err) {
      if (err instanceof ApiError && err.status === 401) {
        askToken(action, token() ? "The token was not accepted; give another one." : null);
        return undefined;
      }
      throw err;
    }
  }

  function askToken(action, why) {
    state.retries.push(action);
    $("auth").hidden = false;
    if (why) $("auth-why").textContent = why;
    $("token").focus();
  }

  $("auth-form").addEventListener("submit", (event) => {
    event.preventDefault();
    sessionStorage.setItem(TOKEN_KEY, $("token").value.trim());
    $("token").value = "";
    $("auth").hidden = true;
    const retries = state.retries;
    state.retries = [];
    for (const retry of retries) guarded(retry).catch(showError);
  });

  // ---- choosing the upload ----

  function describeSize(bytes) {
    if (bytes >= 1024 * 1024) return `${(bytes / 1024 / 1024).toFixed(1)} MiB`;
    if (bytes >= 1024) return `${(bytes / 1024).toFixed(1)} KiB`;
    return `${bytes} bytes`;
  }

  function hiddenPath(path) {
    return path.split("/").some((part) => part.startsWith("."));
  }

  function chooseFolder(entries) {
    const files = entries.filter((e) => !hiddenPath(e.path)).sort((a, b) => (a.path < b.path ? -1 : 1));
    const top = files.length ? files[0].path.split("/")[0] : "";
    choose({ kind: "folder", files, label: `folder ${top} (${files.length} files)` });
  }

  function chooseFile(file) {
    const kind = ARCHIVE.test(file.name) ? "archive" : "file";
    choose({ kind, files: [{ path: file.name, file }], label: `${kind} ${file.name}` });
  }

  function choose(upload) {
    state.upload = upload;
    hideError();
    const bytes = upload.files.reduce((sum, e) => sum + e.file.size, 0);
    $("picked").textContent = `Chosen: ${upload.label}, ${describeSize(bytes)}.`;
    const over = limitExceeded(upload, bytes);
    if (over) {
      showError(new ApiError(413, over));
      setCandidates([], "the upload cannot be sent (see below)");
      return;
    }
    guarded(() => findCandidates(upload)).catch((err) => {
      setCandidates([], "the upload cannot be read (see below)");
      showError(err);
    });
  }

  function limitExceeded(upload, bytes) {
    if (bytes > maxBodyBytes) {
      return `The upload is ${bytes} bytes (${describeSize(bytes)}); the service accepts at most ` +
        `${maxBodyBytes} bytes (${describeSize(maxBodyBytes)}, GEOMCHECK_MAX_BODY_BYTES).`;
    }
    if (upload.files.length > maxFiles) {
      return `The folder holds ${upload.files.length} files; the service accepts at most ${maxFiles} ` +
        "(GEOMCHECK_MAX_FILES).";
    }
    return null;
  }

  async function findCandidates(upload) {
    if (upload.kind === "file") {
      const path = upload.files[0].path;
      setCandidates([{ path, robot: null, included: false }], { path, reason: "the file chosen" });
      return;
    }
    setCandidates(null);
    let request;
    if (upload.kind === "archive") {
      const file = upload.files[0].file;
      request = { method: "POST", body: file, headers: { "Content-Type": archiveType(file.name) } };
    } else {
      // only the descriptions: the meshes are not needed to find the root
      const form = new FormData();
      for (const entry of upload.files) {
        if (DESCRIPTION.test(entry.path)) form.append("files", entry.file, entry.path);
      }
      request = { method: "POST", body: form };
    }
    const response = await api("/v1/root-candidates", request);
    const found = await response.json();
    if (state.upload === upload) setCandidates(found.candidates, found.chosen, found.why);
  }

  function archiveType(name) {
    if (/\.zip$/i.test(name)) return "application/zip";
    if (/\.tar$/i.test(name)) return "application/x-tar";
    return "application/gzip";
  }

  // candidates: null while looking, [] when none (`why` says so), else the list (likely root
  // first); `chosen`: the root the service takes ({path, reason}), null when several robots are
  // equally likely and the person must choose (`why` says so)
  function setCandidates(candidates, chosen = null, why = "no robot description (URDF, xacro, MJCF or SDFormat) in it") {
    const select = $("root");
    select.replaceChildren();
    const usable = Array.isArray(candidates) && candidates.length > 0;
    if (!usable || !chosen) {
      const none = document.createElement("option");
      none.value = "";
      none.textContent = candidates === null ? "looking for root files..." : usable ? "choose the root file" : why;
      select.append(none);
    }
    for (const candidate of candidates || []) {
      const option = document.createElement("option");
      option.value = candidate.path;
      const notes = [
        candidate.robot ? `robot ${candidate.robot}` : null,
        candidate.pulls_in ? `includes ${candidate.pulls_in} file${candidate.pulls_in === 1 ? "" : "s"}` : null,
        candidate.included ? "included by another file" : null,
        candidate.missing ? `lacks ${candidate.missing} file${candidate.missing === 1 ? "" : "s"} of its own package` : null,
      ];
      const note = notes.filter(Boolean).join(", ");
      option.textContent = note ? `${candidate.path} (${note})` : candidate.path;
      select.append(option);
    }
    select.disabled = !usable;
    select.value = usable && chosen ? chosen.path : "";
    state.chosen = usable ? chosen : null;
    state.undecided = usable && !chosen ? `Choose it: ${why.replace(/^name the root file with the 'root' parameter: /, "")}` : null;
    showRoot();
  }

  // the root file whole (a select cuts a long path on a phone) and why it is the one
  function showRoot() {
    const path = $("root").value;
    const chosen = state.chosen;
    $("submit").disabled = !path;
    $("root-chosen").hidden = !path && !state.undecided;
    $("root-path").textContent = path || "none yet";
    if (!path) $("root-why").textContent = state.undecided || "";
    else if (chosen && chosen.path === path) $("root-why").textContent = `Chosen because it is ${chosen.reason}.`;
    else $("root-why").textContent = "Chosen by you.";
  }

  $("root").addEventListener("change", showRoot);

  $("pick-folder").addEventListener("change", (event) => {
    const files = Array.from(event.target.files);
    if (files.length) chooseFolder(files.map((file) => ({ path: file.webkitRelativePath || file.name, file })));
  });

  $("pick-file").addEventListener("change", (event) => {
    const file = event.target.files[0];
    if (file) chooseFile(file);
  });

  const drop = $("drop");
  drop.addEventListener("dragover", (event) => {
    event.preventDefault();
    drop.classList.add("over");
  });
  drop.addEventListener("dragleave", () => drop.classList.remove("over"));
  drop.addEventListener("drop", (event) => {
    event.preventDefault();
    drop.classList.remove("over");
    const items = Array.from(event.dataTransfer.items || []);
    const entries = items.map((item) => (item.webkitGetAsEntry ? item.webkitGetAsEntry() : null)).filter(Boolean);
    if (entries.length === 1 && entries[0].isDirectory) {
      walk(entries[0], "").then(chooseFolder, showError);
    } else if (event.dataTransfer.files.length === 1) {
      chooseFile(event.dataTransfer.files[0]);
    } else {
      showError("Drop one folder, one archive or one description file (URDF, xacro, MJCF, SDFormat).");
    }
  });

  // every file under a dropped folder entry, with its path from the folder's own name down
  async function walk(entry, prefix) {
    if (prefix && entry.name.startsWith(".")) return []; // .git and the like are left out of uploads
    const path = prefix + entry.name;
    if (entry.isFile) {
      const file = await new Promise((resolve, reject) => entry.file(resolve, reject));
      return [{ path, file }];
    }
    const reader = entry.createReader();
    const children = [];
    for (;;) {
      const batch = await new Promise((resolve, reject) => reader.readEntries(resolve, reject));
      if (!batch.length) break;
      children.push(...batch);
    }
    const nested = await Promise.all(children.map((child) => walk(child, `${path}/`)));
    return nested.flat();
  }

  // ---- submitting ----

  function changedOptions() {
    const params = new URLSearchParams();
    for (const input of document.querySelectorAll("[data-option]")) {
      const name = input.dataset.option;
      const fallback = input.dataset.default;
      if (input.dataset.kind === "boolean") {
        const value = input.checked ? "true" : "false";
        if (value !== fallback) params.append(name, value);
      } else if (input.dataset.kind === "list") {
        for (const line of input.value.split("\n")) {
          if (line.trim()) params.append(name, line.trim());
        }
      } else if (input.value.trim() && input.value.trim() !== fallback) {
        params.append(name, input.value.trim());
      }
    }
    return params;
  }

  // the options a check ran with, shown in the form (a shared /checks/{id} page shows that
  // check's options, not the defaults)
  function optionText(value) {
    if (value === null || value === undefined) return "";
    if (Array.isArray(value)) return value.join("\n");
    if (typeof value === "object") return Object.entries(value).map(([k, v]) => `${k}=${v}`).join("\n");
    return String(value);
  }

  function showOptions(options) {
    for (const input of document.querySelectorAll("[data-option]")) {
      const name = input.dataset.option;
      if (!(name in options)) continue;
      const value = options[name];
      if (input.dataset.kind === "boolean") {
        input.checked = value === true || value === "true";
      } else if (input.dataset.kind === "list") {
        const text = optionText(value);
        input.value = text === input.dataset.default.replaceAll(",", "\n") ? "" : text;
      } else {
        input.value = optionText(value);
      }
    }
    $("options-of").hidden = false;
  }

  function submission(upload, root) {
    const params = changedOptions();
    params.set("wait", "false");
    if (upload.kind === "folder") {
      const form = new FormData();
      for (const entry of upload.files) {
        form.append(entry.path === root ? "description" : "files", entry.file, entry.path);
      }
      return { params, init: { method: "POST", body: form } };
    }
    const file = upload.files[0].file;
    params.set("root", root);
    const type = upload.kind === "archive" ? archiveType(file.name) : "application/xml";
    return { params, init: { method: "POST", body: file, headers: { "Content-Type": type } } };
  }

  $("check-form").addEventListener("submit", (event) => {
    event.preventDefault();
    const upload = state.upload;
    const root = $("root").value;
    if (!upload || !root) return;
    hideError();
    $("submit").disabled = true;
    $("submit").textContent = "Sending..."; // a large upload takes a while before the check exists
    guarded(async () => {
      const { params, init } = submission(upload, root);
      const response = await api(`/v1/checks?${params}`, init);
      const check = await response.json();
      follow(check.id, true);
    })
      .catch(showError)
      .finally(() => {
        $("submit").textContent = "Check";
        $("submit").disabled = !$("root").value;
      });
  });

  // ---- following a check ----

  function follow(checkId, push) {
    clearTimeout(state.pollTimer);
    hideError();
    state.checkId = checkId;
    state.check = null;
    const path = `${base}/checks/${encodeURIComponent(checkId)}`;
    if (push && location.pathname !== path) history.pushState({ checkId }, "", path);
    $("progress").hidden = false;
    $("stage-box").hidden = true;
    $("result").hidden = true;
    $("fixes-state").hidden = true;
    if (push) $("progress").scrollIntoView({ block: "start" }); // below the form: in sight once sent
    $("check-id").textContent = checkId;
    $("share").href = path;
    $("share").textContent = new URL(path, location.href).href;
    $("status").textContent = "submitted";
    $("status").className = "badge queued";
    $("cancel").hidden = false;
    $("cancel").disabled = false;
    poll(checkId);
  }

  function poll(checkId) {
    guarded(async () => {
      const response = await api(`/v1/checks/${encodeURIComponent(checkId)}`);
      const check = await response.json();
      if (state.checkId !== checkId) return;
      showCheck(check);
      if (RUNNING.has(check.status) || verifying(check)) state.pollTimer = setTimeout(() => poll(checkId), POLL_MS);
    }).catch(showError);
  }

  function elapsedSeconds(check) {
    if (check.seconds != null && !RUNNING.has(check.status)) return check.seconds;
    const start = Date.parse(check.created);
    const end = check.finished ? Date.parse(check.finished) : Date.now() + state.clockOffset;
    return Math.max(0, (end - start) / 1000);
  }

  function tick() {
    const check = state.check;
    if (!check) return;
    $("elapsed").textContent = `${elapsedSeconds(check).toFixed(1)} s`;
  }
  setInterval(tick, 250);

  // the stage a running check is in and the fraction of its pass done (GET /v1/checks/{id} progress)
  function showProgress(check) {
    const progress = RUNNING.has(check.status) ? check.progress : null;
    $("stage-box").hidden = !progress;
    if (!progress) return;
    $("stage").textContent = `Stage ${progress.stage_index + 1} of ${progress.stages}: ${progress.stage}`;
    $("stage-bar").value = progress.fraction;
    $("stage-percent").textContent = `${Math.round(progress.fraction * 100)} %`;
  }

  function verifying(check) {
    return Boolean(check.fixes && check.fixes.status === "verifying");
  }

  // the offered fixes after the report: verified in a phase of their own, shown with the result
  function showFixes(check) {
    const fixes = check.fixes;
    $("fixes-state").hidden = !fixes;
    if (!fixes) return;
    const progress = verifying(check) ? check.progress : null;
    $("fixes-bar").hidden = !progress;
    let text = {
      verifying: "Verifying the offered fixes: each is applied to a copy of the upload and checked again.",
      verified: "The offered fixes are verified: each was applied to a copy of the upload and checked again.",
      unverified: "The offered fixes are as planned, not verified (verification was turned off).",
      failed: `The offered fixes could not be verified (${fixes.reason || "no reason given"}); the patches are as planned.`,
    }[fixes.status] || "";
    if (progress) {
      text += ` Stage ${progress.stage_index + 1} of ${progress.stages}: ${progress.stage}, ${Math.round(progress.fraction * 100)} %`;
      $("fixes-bar").value = progress.fraction;
    }
    $("fixes-text").textContent = text;
    for (const button of document.querySelectorAll("#downloads [data-patch]")) button.disabled = verifying(check);
  }

  function showCheck(check) {
    const previous = state.check ? state.check.status : null;
    const previousFixes = state.check && state.check.fixes ? state.check.fixes.status : null;
    state.check = check;
    $("status").textContent = check.status;
    $("status").className = `badge ${check.status}`;
    $("cancel").hidden = !RUNNING.has(check.status);
    showProgress(check);
    tick();
    if (previous === null && check.options) showOptions(check.options);
    if (check.status === previous) {
      if (check.status === "succeeded") {
        // the verified report replaces the one answered first (its patches, its fixes
        // section); while the verification runs, its stage and bar move on
        if (previousFixes === "verifying" && !verifying(check)) showResult(check, false);
        else showFixes(check);
      }
      return;
    }
    if (check.status === "succeeded") showResult(check);
    if (check.status === "failed") showError(new ApiError(check.http_status || 422, check.reason || "the check failed"));
    if (!RUNNING.has(check.status)) loadRecent(state.page);
  }

  $("cancel").addEventListener("click", () => {
    const checkId = state.checkId;
    $("cancel").disabled = true;
    guarded(async () => {
      await api(`/v1/checks/${encodeURIComponent(checkId)}`, { method: "DELETE" });
      poll(checkId);
    }).catch((err) => {
      $("cancel").disabled = false;
      if (err instanceof ApiError && (err.status === 404 || err.status === 405) && state.check && RUNNING.has(state.check.status)) {
        showError("This service cannot cancel checks (it has no DELETE /v1/checks/{id}).");
      } else {
        showError(err);
      }
    });
  });

  window.addEventListener("popstate", () => start());

  // ---- the result ----

  function plural(n, word) {
    return `${n} ${word}${n === 1 ? "" : "s"}`;
  }

  function showResult(check, focus = true) {
    const report = check.report;
    const summary = check.summary || report.summary;
    $("result").hidden = false;
    $("verdict").textContent = check.verdict;
    $("verdict").className = `badge ${check.verdict}`;
    $("robot").textContent = check.robot || "";
    $("counts").textContent = `${plural(summary.error, "error")}, ${plural(summary.warning, "warning")}, ${summary.info} info`;
    const fixable = report.diagnostics.filter((d) => d.fix).length;
    $("fixable").textContent = fixable ? `(${fixable} with a suggested fix)` : "";
    for (const button of document.querySelectorAll("#downloads [data-link]")) {
      button.hidden = !check.links[button.dataset.link];
    }
    // the fixes as patches (GET .../fixes.patch), offered when the report planned some
    const fixes = (report.sections || {}).fixes || {};
    for (const button of document.querySelectorAll("#downloads [data-patch]")) {
      const patch = fixes[button.dataset.patch];
      button.hidden = !patch || (button.dataset.patch === "unsafe_patch" && patch === fixes.safe_patch);
    }
    showFixes(check);
    const rows = report.diagnostics.map(findingRow);
    $("findings").tBodies[0].replaceChildren(...rows);
    $("findings").hidden = rows.length === 0;
    $("no-findings").hidden = rows.length !== 0;
    $("findings-count").textContent = String(rows.length);
    $("report").srcdoc = "";
    guarded(async () => {
      const response = await api(`/v1/checks/${encodeURIComponent(check.id)}/report.html`);
      const page = await response.text();
      if (state.checkId === check.id) $("report").srcdoc = page;
    }).catch(showError);
    if (focus) $("result-title").focus();
  }

  function cell(text, className) {
    const td = document.createElement("td");
    td.textContent = text;
    if (className) td.className = className;
    return td;
  }

  function findingRow(d) {
    const tr = document.createElement("tr");
    const subject = d.links ? d.links.join(" / ") : d.joint || d.link || "robot";
    const rule = cell(`${d.code} `);
    const name = document.createElement("small");
    name.textContent = d.name;
    rule.append(name);
    // the help, with the rest of the detail, is in the report below
    tr.append(rule, cell(d.severity, `severity ${d.severity}`), cell(subject + (d.about ? ` (${d.about})` : "")), cell(d.message));
    return tr;
  }

  $("downloads").addEventListener("click", (event) => {
    const button = event.target.closest("button");
    if (!button || !state.check) return;
    const check = state.check;
    const path = button.dataset.link ? check.links[button.dataset.link] : check.links.self + button.dataset.suffix;
    guarded(() => download(path)).catch(showError);
  });

  // fetched rather than linked so that a token, when the service needs one, goes with the request
  async function download(path) {
    const response = await fetch(path, { headers: token() ? { Authorization: `Bearer ${token()}` } : {} });
    if (!response.ok) throw new ApiError(response.status, await detailOf(response));
    const disposition = response.headers.get("Content-Disposition") || "";
    const named = /filename="?([^";]+)"?/.exec(disposition);
    const link = document.createElement("a");
    link.href = URL.createObjectURL(await response.blob());
    link.download = named ? named[1] : path.split("/").pop();
    document.body.append(link);
    link.click();
    link.remove();
    setTimeout(() => URL.revokeObjectURL(link.href), 60000);
  }

  // ---- errors ----

  // "urdf/base.urdf.xacro:12:5: GC101 malformed-xml: ..." -> file, line, column, message
  const LOCATED = /^([^\s:][^:]*):(\d+)(?::(\d+))?:\s*(.*)$/;

  function showError(err) {
    const text = typeof err === "string" ? err : err.message || String(err);
    const status = err instanceof ApiError ? err.status : null;
    $("error").hidden = false;
    $("error-title").textContent = status === 413 ? "A limit was exceeded" : "The check could not run";
    $("error-message").textContent = text;
    const where = LOCATED.exec(text);
    $("error-where").hidden = !where;
    $("error-frame").hidden = true;
    if (!where) return;
    $("error-file").textContent = where[1];
    $("error-line").textContent = where[3] ? `${where[2]}, column ${where[3]}` : where[2];
    const shown = text;
    localText(where[1])
      .then((source) => {
        // only if the message is still the one shown: a newer error may have replaced it
        if (source !== null && $("error-message").textContent === shown) {
          showFrame(source, Number(where[2]), Number(where[3] || 0));
        }
      })
      .catch(() => {}); // the lines are a help; the message already says what is wrong
  }

  function hideError() {
    $("error").hidden = true;
  }

  // the text of the uploaded file a message names (report paths may drop or add the upload's top folder)
  async function localText(path) {
    const upload = state.upload;
    if (!upload) return null;
    if (upload.kind === "archive") return window.geomcheckArchive.read(upload.files[0].file, path);
    const match = upload.files.find(
      (e) => e.path === path || e.path.endsWith(`/${path}`) || path.endsWith(`/${e.path}`),
    );
    return match ? match.file.text() : null;
  }

  function showFrame(source, line, column) {
    const lines = source.replace(/\r?\n$/, "").split(/\r?\n/);
    const first = Math.max(1, line - 3);
    const last = Math.min(lines.length, line + 3);
    const width = String(last).length;
    const frame = $("error-frame");
    frame.replaceChildren();
    for (let n = first; n <= last; n += 1) {
      const row = document.createElement("span");
      row.className = n === line ? "at" : "";
      row.textContent = `${n === line ? ">" : " "} ${String(n).padStart(width)} | ${lines[n - 1]}\n`;
      frame.append(row);
      if (n === line && column > 0) {
        const caret = document.createElement("span");
        caret.className = "at";
        caret.textContent = `  ${" ".repeat(width)} | ${" ".repeat(column - 1)}^\n`;
        frame.append(caret);
      }
    }
    frame.hidden = false;
  }

  // ---- recent checks ----

  // "fail" (the robot has findings at the failing severity) and "failed" (the check could not
  // run) must not look alike
  const BADGE_TEXT = { fail: "fail: findings", failed: "could not run", pass: "pass" };

  function loadRecent(page) {
    const cursor = state.cursors[page];
    const params = new URLSearchParams(); // the service's page size (GEOMCHECK_PAGE_SIZE)
    if (cursor) params.set("cursor", cursor);
    guarded(async () => {
      const response = await api(`/v1/checks?${params}`);
      const data = await response.json();
      state.page = page;
      state.nextCursor = data.next_cursor;
      state.cursors[page + 1] = data.next_cursor;
      $("recent-table").tBodies[0].replaceChildren(...data.items.map(recentRow));
      $("recent-table").hidden = data.items.length === 0;
      $("recent-empty").hidden = data.items.length !== 0;
      $("newer").disabled = page === 0;
      $("older").disabled = !data.next_cursor;
      $("pager").hidden = page === 0 && !data.next_cursor;
    }).catch(showError);
  }

  function recentRow(check) {
    const tr = document.createElement("tr");
    const robot = document.createElement("td");
    const link = document.createElement("a");
    link.href = `${base}/checks/${encodeURIComponent(check.id)}`;
    link.textContent = check.robot || check.source;
    link.addEventListener("click", (event) => {
      event.preventDefault();
      hideError();
      follow(check.id, true);
    });
    robot.append(link);
    const verdict = document.createElement("td");
    const badge = document.createElement("span");
    const state = check.verdict || check.status;
    badge.className = `badge ${state}`;
    badge.textContent = BADGE_TEXT[state] || state;
    verdict.append(badge);
    if (check.status === "failed" && check.reason) {
      const why = document.createElement("span");
      why.className = "reason";
      why.textContent = check.reason;
      why.title = check.reason;
      verdict.append(why);
    }
    const summary = check.summary || {};
    const when = new Date(check.created);
    const time = document.createElement("td");
    const stamp = document.createElement("time");
    stamp.dateTime = check.created;
    stamp.textContent = when.toLocaleString();
    time.append(stamp);
    tr.append(robot, verdict, cell(summary.error ?? ""), cell(summary.warning ?? ""), cell(summary.info ?? ""), time);
    return tr;
  }

  $("newer").addEventListener("click", () => loadRecent(Math.max(0, state.page - 1)));
  $("older").addEventListener("click", () => loadRecent(state.page + 1));

  // ---- start ----

  function start() {
    const match = /\/checks\/([^/]+)$/.exec(location.pathname);
    const checkId = match ? decodeURIComponent(match[1]) : null;
    if (checkId) {
      follow(checkId, false);
    } else {
      clearTimeout(state.pollTimer);
      state.checkId = null;
      $("progress").hidden = true;
      $("result").hidden = true;
    }
    loadRecent(0);
  }

  start();
})();
