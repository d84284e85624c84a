// A headless client of socc-view's page protocol (/ws) for the benchmark: counts the bytes and
// messages it receives and prints them as JSON on SIGTERM. --stall: reads nothing after the
// handshake (a browser tab that hangs), to show that it slows nobody else.
// Usage: node page_client.cjs WS_URL [--stall]
const WebSocket = require('ws');

const [url, flag] = process.argv.slice(2);
if (!url) { console.error('usage: node page_client.cjs WS_URL [--stall]'); process.exit(2); }
const stall = flag === '--stall';
const counts = { bytes: 0, messages: 0, binary: 0, text: 0 };
const ws = new WebSocket(url);
ws.on('open', () => { if (stall) ws._socket.pause(); });
setInterval(() => {}, 1000);  // a paused socket alone does not keep node running
ws.on('message', (data, isBinary) => {
  counts.bytes += data.length;
  ++counts.messages;
  if (isBinary) ++counts.binary; else ++counts.text;
});
ws.on('close', (code) => { console.error(`page_client: closed (${code}) after ${counts.bytes} bytes`); });
ws.on('error', (e) => { console.error(`page_client: ${e.message}`); process.exit(1); });
process.on('SIGTERM', () => { console.log(JSON.stringify(counts)); process.exit(0); });
