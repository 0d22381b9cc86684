// The page is served by `contactmap serve` at `/`, its files under `/assets/` (web/dist/assets).
import { defineConfig } from 'vite';

export default defineConfig({
  base: '/',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    // HiGlass with React and pixi.js is one large chunk; vite's 500 kB warning says nothing new.
    chunkSizeWarningLimit: 4096,
  },
  // `npx vite` (the dev server) sends the API to a running `contactmap serve --port 8989`.
  server: { proxy: { '/api': 'http://127.0.0.1:8989' } },
});
