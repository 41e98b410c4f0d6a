// The study pages' client of the server's JSON-RPC API: one WebSocket, calls answered by id,
// notifications to a handler, and a reconnect when the link drops.
"use strict";

const $ = (id) => document.getElementById(id);

class Rpc {
  constructor(onOpen, onNotification, onState) {
    Object.assign(this, { onOpen, onNotification, onState, nextId: 1, pending: new Map() });
    this.connect();
  }

  connect() {
    this.ws = new WebSocket(`ws://${location.host}/websocket`);
    this.ws.onmessage = (event) => {
      const m = JSON.parse(event.data);
      if (m.id !== undefined && this.pending.has(m.id)) {
        const { resolve, reject } = this.pending.get(m.id);
        this.pending.delete(m.id);
        return m.error ? reject(new Error(m.error.message)) : resolve(m.result);
      }
      if (m.method) this.onNotification(m.method, m.params);
    };
    this.ws.onopen = () => { this.onState(true); this.onOpen(); };
    this.ws.onclose = () => {
      this.onState(false);
      for (const { reject } of this.pending.values()) reject(new Error("disconnected"));
      this.pending.clear();
      setTimeout(() => this.connect(), 1000);
    };
  }

  call(method, params = {}) {
    return new Promise((resolve, reject) => {
      if (this.ws.readyState !== WebSocket.OPEN) return reject(new Error("not connected"));
      const id = this.nextId++;
      this.pending.set(id, { resolve, reject });
      this.ws.send(JSON.stringify({ jsonrpc: "2.0", id, method, params }));
    });
  }
}
