// The names the README's JavaScript example uses without declaring them.
import type * as Three from 'three';
declare global {
  const fileOrResponseOrStream: Blob;
  const abortController: AbortController;
  const scene: Three.Scene;
  const THREE: typeof Three;
}
export {};
