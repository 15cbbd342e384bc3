// The README's union example imports manifold-3d, an optional peer dependency of stltopo that
// this consumer does not install (its dependencies pull in an image library with native
// binaries). This is the part of manifold-3d's own declaration (manifold.d.ts, 3.5.4) that the
// example uses; stltopo's UnionOptions takes the module as it is (`unknown`).
declare module 'manifold-3d' {
  interface ManifoldToplevel {
    setup: () => void;
  }
  export default function Module(config?: { locateFile: () => string }): Promise<ManifoldToplevel>;
}
