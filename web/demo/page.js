// The demo page's shared pieces: the query helper and the one 3D viewer (viewer.js).
import { Viewer } from './viewer.js';

export const $ = (selector) => document.querySelector(selector);
export const viewer = new Viewer($('#viewport'));
if (import.meta.env?.DEV) window.stltopoDemo = { viewer }; // for poking around in devtools
