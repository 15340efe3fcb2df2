// The service's HTTP API (docs/service.md) as the page uses it: every call carries the bearer
// token; a refusal becomes an Error whose message is the service's own sentence.

export class ApiError extends Error {
  constructor(status, sentence) {
    super(sentence);
    this.status = status;
  }
}

export class Api {
  constructor(token) {
    this.token = token;
  }

  async request(method, path, body) {
    const response = await fetch(path, {
      method,
      body,
      headers: { Authorization: `Bearer ${this.token}` },
    });
    if (!response.ok) {
      let sentence = `${response.status} ${response.statusText}`;
      try {
        sentence = (await response.json()).error ?? sentence;
      } catch {
        // not JSON: keep the status line
      }
      throw new ApiError(response.status, sentence);
    }
    return response;
  }

  // POST /v1/{kind}: the mesh file and the options object; resolves to the job's id.
  async submit(kind, file, options) {
    const form = new FormData();
    form.append('mesh', file, file.name);
    form.append('options', JSON.stringify(options ?? {}));
    const response = await this.request('POST', `/v1/${kind}`, form);
    return (await response.json()).id;
  }

  cancel(id) {
    return this.request('DELETE', `/v1/jobs/${id}`);
  }

  async result(id) {
    return (await this.request('GET', `/v1/jobs/${id}/result`)).blob();
  }

  // Follows GET /v1/jobs/{id}/events (server-sent events, read through fetch so that the token
  // travels in a header, which EventSource cannot send): calls onRecord with each job record,
  // resolves with the last one once the job has ended.
  async follow(id, onRecord) {
    const response = await this.request('GET', `/v1/jobs/${id}/events`);
    const reader = response.body.pipeThrough(new TextDecoderStream()).getReader();
    let buffered = '';
    let last = null;
    for (;;) {
      const { value, done } = await reader.read();
      if (done) break;
      buffered += value;
      let end;
      while ((end = buffered.indexOf('\n\n')) >= 0) {
        const event = buffered.slice(0, end);
        buffered = buffered.slice(end + 2);
        const data = event
          .split('\n')
          .filter((line) => line.startsWith('data:'))
          .map((line) => line.slice(5).trimStart())
          .join('\n');
        if (!data) continue;  // a keep-alive comment
        last = JSON.parse(data);
        onRecord(last);
      }
    }
    if (!last || !['done', 'failed', 'cancelled'].includes(last.state))
      throw new Error('the connection to the service closed before the job ended');
    return last;
  }
}
