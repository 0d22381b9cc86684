//! The text outputs of the TAD callers, as the peer tools write them: the per-bin tracks
//! (cooltools' insulation table, the directionality index of Dixon et al. with its HMM states,
//! TopDom's `.bed`-like binSignal table, Armatus' domains) and BED files of boundaries and domains.

use super::call::{TadCalls, TadTrack};
use super::directionality::DirectionalityTable;
use super::domains::Domain;
use super::hmm::DiState;
use super::insulation::{InsulationTable, TrackValues};
use super::topdom::{TopDomRegion, TopDomTag};
use crate::genome::BinTable;
use crate::io::tables::{write_real, write_u64};

impl TadTrack {
    /// The per-bin track as text with a header line: cooltools' insulation table
    /// (`chrom start end region is_bad_bin [dist_bad_bin] log2_insulation_score_W n_valid_pixels_W
    /// ... boundary_strength_W ... is_boundary_W ...`), the directionality table
    /// (`... directionality_ratio_W directionality_index_W di_state`), TopDom's
    /// (`chrom start end bin_signal local_min pvalue segment`) or Armatus' domains
    /// (`chrom start end level gamma score`).
    pub fn to_tsv(&self, bins: &BinTable) -> Vec<u8> {
        match self {
            TadTrack::Insulation(table, names) => insulation_text(bins, table, names),
            TadTrack::Directionality(table, states) => directionality_text(bins, table, states),
            TadTrack::TopDom(regions) => topdom_text(bins, regions),
            TadTrack::Armatus(domains) => armatus_text(bins, domains),
        }
    }
}

impl TadCalls {
    /// A summary as JSON (what `tads --json` prints): the input `uri`, the `method`, the label,
    /// the numbers of boundaries and domains, and per insulation window its boundaries and
    /// threshold (null when not finite).
    pub fn summary_json(&self, uri: &str, method: &str) -> serde_json::Value {
        let mut value = serde_json::json!({
            "uri": uri,
            "method": method,
            "label": self.label,
            "n_boundaries": self.boundaries.len(),
            "n_domains": self.domains.len(),
        });
        if let TadTrack::Insulation(table, _) = &self.track {
            value["windows"] = table
                .tracks
                .iter()
                .map(|t| {
                    serde_json::json!({
                        "window_bp": t.window_bp,
                        "n_boundaries": t.is_boundary.iter().filter(|&&b| b).count(),
                        "cutoff": t.cutoff, // null when not finite
                    })
                })
                .collect();
        }
        value
    }

    /// The boundaries as BED: `chrom start end label strength` (`.` for no strength), one bin
    /// each.
    pub fn boundaries_bed(&self, bins: &BinTable) -> Vec<u8> {
        let (boundaries, label) = (&self.boundaries, &self.label);
        let mut text = Vec::new();
        for boundary in boundaries {
            push_bin(&mut text, bins, boundary.bin);
            text.push(b'\t');
            text.extend_from_slice(label.as_bytes());
            text.push(b'\t');
            push_score(&mut text, boundary.strength);
            text.push(b'\n');
        }
        text
    }

    /// The domains as BED: `chrom start end label[_levelN] score` (`.` for no score).
    pub fn domains_bed(&self, bins: &BinTable) -> Vec<u8> {
        let (domains, label) = (&self.domains, self.label.as_str());
        let mut text = Vec::new();
        for domain in domains {
            push_span(&mut text, bins, domain);
            text.push(b'\t');
            text.extend_from_slice(label.as_bytes());
            if domain.level > 0 || label == "armatus" {
                text.extend_from_slice(format!("_level{}", domain.level).as_bytes());
            }
            text.push(b'\t');
            push_score(&mut text, domain.score);
            text.push(b'\n');
        }
        text
    }
}

fn push_bin(text: &mut Vec<u8>, bins: &BinTable, bin: usize) {
    push_bins(text, bins, bin, bin + 1);
}

fn push_bool(text: &mut Vec<u8>, value: bool) {
    text.extend_from_slice(if value { b"True" } else { b"False" });
}

fn insulation_text(bins: &BinTable, table: &InsulationTable, region_names: &[String]) -> Vec<u8> {
    let mut text = Vec::with_capacity(128 * (table.bins.len() + 1));
    text.extend_from_slice(b"chrom\tstart\tend\tregion\tis_bad_bin");
    if table.dist_bad_bin.is_some() {
        text.extend_from_slice(b"\tdist_bad_bin");
    }
    let columns = table.track_columns();
    for (name, _) in &columns {
        text.push(b'\t');
        text.extend_from_slice(name.as_bytes());
    }
    text.push(b'\n');
    for (row, &bin) in table.bins.iter().enumerate() {
        push_bin(&mut text, bins, bin);
        text.push(b'\t');
        text.extend_from_slice(region_names[table.region[row]].as_bytes());
        text.push(b'\t');
        push_bool(&mut text, table.is_bad_bin[row]);
        if let Some(d) = &table.dist_bad_bin {
            text.push(b'\t');
            write_u64(&mut text, d[row] as u64);
        }
        for (_, values) in &columns {
            text.push(b'\t');
            match values {
                TrackValues::Real(v) => write_real(&mut text, v[row]),
                TrackValues::Flag(v) => push_bool(&mut text, v[row]),
            }
        }
        text.push(b'\n');
    }
    text
}

fn directionality_text(
    bins: &BinTable,
    table: &DirectionalityTable,
    states: &[Option<DiState>],
) -> Vec<u8> {
    let w = table.window_bp;
    let mut text = Vec::with_capacity(96 * (table.bins.len() + 1));
    text.extend_from_slice(
        format!(
            "chrom\tstart\tend\tbad_bin_masked\tdirectionality_ratio_{w}\tdirectionality_index_{w}\tdi_state\n"
        )
        .as_bytes(),
    );
    for (row, &bin) in table.bins.iter().enumerate() {
        push_bin(&mut text, bins, bin);
        text.push(b'\t');
        push_bool(&mut text, table.bad_bin_masked[row]);
        text.push(b'\t');
        write_real(&mut text, table.ratio[row]);
        text.push(b'\t');
        write_real(&mut text, table.index[row]);
        text.push(b'\t');
        // A masked bin (DI NaN) has no state: `nan`, as the numbers beside it.
        text.extend_from_slice(match states[row] {
            Some(DiState::Upstream) => b"upstream".as_slice(),
            Some(DiState::Neutral) => b"neutral",
            Some(DiState::Downstream) => b"downstream",
            None => b"nan",
        });
        text.push(b'\n');
    }
    text
}

fn topdom_text(bins: &BinTable, regions: &[TopDomRegion]) -> Vec<u8> {
    let mut text = Vec::new();
    text.extend_from_slice(b"chrom\tstart\tend\tbin_signal\tlocal_min\tpvalue\tsegment\n");
    for region in regions {
        let mut tags = vec![b"gap".as_slice(); region.bin_signal.len()];
        for (domain, tag) in &region.segments {
            let name: &[u8] = match tag {
                TopDomTag::Gap => b"gap",
                TopDomTag::Domain => b"domain",
                TopDomTag::Boundary => b"boundary",
            };
            for bin in domain.start_bin..domain.end_bin {
                if let Some(slot) = tags.get_mut(bin - region.first_bin) {
                    *slot = name;
                }
            }
        }
        for (k, &signal) in region.bin_signal.iter().enumerate() {
            push_bin(&mut text, bins, region.first_bin + k);
            text.push(b'\t');
            write_real(&mut text, signal);
            text.push(b'\t');
            push_bool(&mut text, region.is_local_min[k]);
            text.push(b'\t');
            write_real(&mut text, region.pvalue[k]);
            text.push(b'\t');
            text.extend_from_slice(tags[k]);
            text.push(b'\n');
        }
    }
    text
}

fn armatus_text(bins: &BinTable, domains: &[(Domain, f64)]) -> Vec<u8> {
    let mut text = Vec::new();
    text.extend_from_slice(b"chrom\tstart\tend\tlevel\tgamma\tscore\n");
    for (domain, gamma) in domains {
        push_span(&mut text, bins, domain);
        text.push(b'\t');
        write_u64(&mut text, u64::from(domain.level));
        text.push(b'\t');
        write_real(&mut text, *gamma);
        text.push(b'\t');
        write_real(&mut text, domain.score);
        text.push(b'\n');
    }
    text
}

/// chrom, start of the first bin, end of the last bin.
fn push_span(text: &mut Vec<u8>, bins: &BinTable, domain: &Domain) {
    push_bins(text, bins, domain.start_bin, domain.end_bin);
}

/// chrom, start, end of the bins `first..end` (one chromosome).
fn push_bins(text: &mut Vec<u8>, bins: &BinTable, first: usize, end: usize) {
    let (first, last) = (bins.bin(first), bins.bin(end - 1));
    text.extend_from_slice(bins.chroms()[first.chrom_id].name.as_bytes());
    text.push(b'\t');
    write_u64(text, first.start);
    text.push(b'\t');
    write_u64(text, last.end);
}

fn push_score(text: &mut Vec<u8>, value: f64) {
    if value.is_finite() {
        write_real(text, value);
    } else {
        text.push(b'.');
    }
}
