// The live view's client: the page served by `chainsim run --live` connects
// back to the server's WebSocket and receives the run as it happens:
//   {"type":"started","scene":{...},"header":"t_s,...","files":{...}}
//       (files: the environment's mesh files, as "mesh_files" of a replay; optional)
//   {"type":"rows","csv":"<trace lines>"}        (batched)
//   {"type":"bus","lines":"<bus.log lines>"}     (batched)
//   {"type":"gap","rows":N}                      (rows dropped for this page)
//   {"type":"finished","summary":{...}}
//   {"type":"reload","why":"..."}               (`chainsim run --watch`: a new run follows)
// and answers {"type":"ack","finished":true} once it has the end.
export function connectLive(handlers) {
  const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`;
  const ws = new WebSocket(url);
  let finished = false;
  ws.onopen = () => handlers.status('connected: waiting for the run');
  ws.onmessage = (ev) => {
    const msg = JSON.parse(ev.data);
    switch (msg.type) {
      case 'started': handlers.started(msg.scene, msg.header, msg.files); handlers.status('running'); break;
      case 'rows': handlers.rows(msg.csv); break;
      case 'bus': handlers.bus(msg.lines); break;
      case 'gap': handlers.gap?.(msg.rows); break;
      case 'reload': handlers.reload?.(msg.why); break;
      case 'finished':
        finished = true;
        handlers.finished(msg.summary);
        handlers.status('finished');
        ws.send(JSON.stringify({ type: 'ack', finished: true }));
        break;
      default: break;
    }
  };
  ws.onclose = () => {
    if (!finished) handlers.status('disconnected: the run is over or the server has stopped');
  };
  ws.onerror = () => handlers.status('no connection to the live server');
  return ws;
}
