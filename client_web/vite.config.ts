import { defineConfig } from 'vitest/config';

// `npm run dev` proxies the WebSocket to a `penumbra serve` at PENUMBRA_SERVER (default :8080);
// `npm run build` writes dist/, which `penumbra serve` serves by default.
const server = process.env['PENUMBRA_SERVER'] ?? 'http://127.0.0.1:8080';

export default defineConfig({
  base: './',
  build: { outDir: 'dist', emptyOutDir: true, target: 'es2022', sourcemap: true },
  server: { proxy: { '/ws': { target: server.replace(/^http/, 'ws'), ws: true } } },
  test: { include: ['test/**/*.test.ts'], environment: 'node' },
});
