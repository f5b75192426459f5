// fetch for exprclone's pages (the clone page and the study's): the server's {"error"} comes out as an Error, with the
// answer's status, and no request waits forever. No build step: a classic script, loaded before the page's own.
"use strict";

// timeout: milliseconds before the request is given up (the clone page's longest work, a comparison sheet, is well within)
async function call(url, options = {}, timeout = 180000) {
  const controller = new AbortController();
  const timer = setTimeout(() => controller.abort(), timeout);
  let response;
  try {
    response = await fetch(url, { ...options, signal: controller.signal });
  } catch (e) {
    throw new Error(e.name === "AbortError" ? "the server took too long to answer" : "the server cannot be reached");
  } finally {
    clearTimeout(timer);
  }
  if (!response.ok) {
    let message = `the server answered ${response.status}`;
    try { message = (await response.json()).error || message; } catch (e) { /* not JSON */ }
    const error = new Error(message);
    error.status = response.status;
    throw error;
  }
  return response;
}
