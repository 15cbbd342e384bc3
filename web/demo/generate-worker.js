// Builds a generated sample off the main thread: receives { name }, answers with the STL bytes
// (transferred) or { error }.
import { generators } from './generate.js';

self.onmessage = ({ data: { name } }) => {
  try {
    const buffer = generators[name]();
    self.postMessage({ buffer }, [buffer]);
  } catch (error) {
    self.postMessage({ error: String(error?.message ?? error) });
  }
};
