// juicebox.js' reader (hic-straw) opens a .hic that `contactmap serve` serves by URL, through
// range requests and CORS: node web/test/straw.mjs URL CHROM RESOLUTION prints the file's
// resolutions and norms and CHROM's contact records (count and sum), for the caller to compare
// with `contactmap dump`.
import HicStraw from '../node_modules/hic-straw/dist/hic-straw.esm.js';

const [url, chrom, resolution] = process.argv.slice(2);
const straw = new HicStraw({ url });
const meta = await straw.getMetaData();
const norms = await straw.getNormalizationOptions();
const length = meta.chromosomes.find((c) => c.name === chrom)?.size;
if (!length) {
  console.log(`straw: ${chrom} is not among the file's chromosomes`);
  process.exit(1);
}
const region = { chr: chrom, start: 0, end: length };
const records = await straw.getContactRecords('NONE', region, region, 'BP', Number(resolution));
let sum = 0;
for (const record of records) sum += record.counts;
console.log(`straw: resolutions ${meta.resolutions.join(',')} norms ${norms.join(',')}`);
console.log(`straw: records ${records.length} sum ${sum}`);
