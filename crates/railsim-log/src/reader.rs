//! Reading logs back: finished ones through their summary and index, truncated ones (a killed
//! run) by a linear scan that stops cleanly after the last complete chunk.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use mcap::records::Record;
use mcap::sans_io::{
    IndexedReadEvent, IndexedReader, IndexedReaderOptions, LinearReadEvent, LinearReader,
    LinearReaderOptions, SummaryReadEvent, SummaryReader, SummaryReaderOptions,
};

use crate::error::{LogError, Result};
use crate::messages::LogMessage;
use crate::writer::{FORMAT_METADATA, FORMAT_VERSION, SCENE_ATTACHMENT, SCENE_METADATA};

/// One channel of a log, with what the data section holds for it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChannelInfo {
    /// MCAP channel id.
    pub id: u16,
    /// Topic, e.g. `/bodies/wheelset_1`.
    pub topic: String,
    /// Schema name, e.g. `railsim.BodyState`.
    pub schema_name: String,
    /// Schema encoding (`jsonschema` for railsim logs).
    pub schema_encoding: String,
    /// The schema itself (JSON text for `jsonschema`).
    pub schema: Vec<u8>,
    /// Message encoding (`json` for railsim logs).
    pub message_encoding: String,
    /// Number of messages readable on this channel.
    pub message_count: u64,
    /// \[ns\] log time of the earliest message, if any
    pub first_ns: Option<u64>,
    /// \[ns\] log time of the latest message, if any
    pub last_ns: Option<u64>,
}

/// Which messages to visit: topics and an inclusive log-time range.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Query {
    /// Topics to include; `None` = all.
    pub topics: Option<Vec<String>>,
    /// \[ns\] earliest log time included
    pub start_ns: Option<u64>,
    /// \[ns\] latest log time included
    pub end_ns: Option<u64>,
}

impl Query {
    /// All messages.
    pub fn all() -> Self {
        Self::default()
    }

    /// Only the given topics.
    pub fn topics<S: Into<String>>(topics: impl IntoIterator<Item = S>) -> Self {
        Query {
            topics: Some(topics.into_iter().map(Into::into).collect()),
            ..Self::default()
        }
    }

    /// Restricts to log times in `[start_ns, end_ns]` (inclusive).
    pub fn between(mut self, start_ns: u64, end_ns: u64) -> Self {
        self.start_ns = Some(start_ns);
        self.end_ns = Some(end_ns);
        self
    }

    fn accepts_time(&self, t_ns: u64) -> bool {
        self.start_ns.is_none_or(|s| t_ns >= s) && self.end_ns.is_none_or(|e| t_ns <= e)
    }
}

/// One message as stored, borrowed for the duration of a callback.
#[derive(Debug, Clone, Copy)]
pub struct LogMessageRef<'a> {
    /// The channel the message was written on.
    pub channel: &'a ChannelInfo,
    /// Per-channel sequence number, from 0.
    pub sequence: u32,
    /// \[ns\] log time (= simulation time)
    pub log_time_ns: u64,
    /// \[ns\] publish time (= log time in railsim logs)
    pub publish_time_ns: u64,
    /// The encoded message (JSON text).
    pub data: &'a [u8],
}

/// A railsim log opened for reading.
///
/// [`LogReader::open`] reads the summary if the file has one and then scans the data section
/// once (streaming: memory bounded by one chunk) to count messages and find each channel's time
/// range; for a finished file the counts are checked against the summary's statistics. A file
/// without a summary (the writer was killed) is read up to its last complete chunk; what
/// follows is ignored and described by [`LogReader::truncation`].
#[derive(Debug)]
pub struct LogReader {
    path: PathBuf,
    summary: Option<mcap::Summary>,
    channels: Vec<ChannelInfo>,
    by_id: HashMap<u16, usize>,
    metadata: BTreeMap<String, BTreeMap<String, String>>,
    attachments: Vec<(String, String, Vec<u8>)>,
    finished: bool,
    truncation: Option<String>,
}

/// Where a linear scan ended.
struct ScanEnd {
    /// Why the scan stopped before a footer, if it did.
    truncation: Option<String>,
}

fn corrupt(path: &Path, what: impl Into<String>, expected: impl Into<String>) -> LogError {
    LogError::Corrupt {
        path: path.to_path_buf(),
        what: what.into(),
        expected: expected.into(),
    }
}

fn io_err<'p>(
    path: &'p Path,
    action: &'static str,
) -> impl FnOnce(std::io::Error) -> LogError + 'p {
    move |source| LogError::Io {
        path: path.to_path_buf(),
        action,
        source,
    }
}

/// How many bytes to hand a reader that asks for `need` at `pos` of a file of `len` bytes: never
/// more than the file still holds (at least 1, so that the end of the file is seen), since a
/// damaged length field can ask for exabytes, which the reader would allocate.
/// \[B\] the largest record or chunk (compressed or decompressed) the reader accepts: far
/// above what the writer produces (chunks of 256 KiB by default), far below what a damaged length
/// field can ask for. A damaged chunk header's decompressed size is checked against it before
/// anything is allocated.
const RECORD_LENGTH_LIMIT: usize = 256 << 20;

fn read_size(need: usize, pos: u64, len: u64) -> usize {
    let left = usize::try_from(len.saturating_sub(pos)).unwrap_or(usize::MAX);
    need.min(left).max(1)
}

/// \[B\] the footer record (opcode, length, 20-byte body) and the closing magic: the last bytes
/// of a finished MCAP file.
const FOOTER_AND_MAGIC: u64 = 1 + 8 + 20 + 8;

/// What the end of a file says about its summary.
enum Tail {
    /// The summary, found through the footer.
    Summary(Box<mcap::Summary>),
    /// A footer (its opcode and the closing magic in place) that records no summary section
    /// (summary start 0, allowed by MCAP): a finished file without a summary.
    NoSummary,
    /// A footer in place whose summary does not read: the footer's summary start is damaged or
    /// the summary section is.
    Unreadable {
        /// \[B\] where the footer is
        footer: u64,
        /// \[B\] where it puts the summary
        summary_start: u64,
        /// the summary reader's error
        error: String,
    },
    /// No footer: the writer stopped before finishing (or the file is too short for one).
    Unfinished,
}

/// Reads the summary section of the `len`-byte file through its footer. A footer that is
/// present (its opcode and the closing magic in place) but puts the summary at or beyond its own
/// start is damaged: an error.
fn read_summary(path: &Path, file: &mut File, len: u64) -> Result<Tail> {
    if len < mcap::MAGIC.len() as u64 + FOOTER_AND_MAGIC {
        return Ok(Tail::Unfinished);
    }
    let footer = len - FOOTER_AND_MAGIC;
    let mut tail = [0u8; FOOTER_AND_MAGIC as usize];
    file.seek(SeekFrom::Start(footer))
        .and_then(|_| file.read_exact(&mut tail))
        .map_err(io_err(path, "reading the footer"))?;
    // opcode, record length (8), summary start (8), summary offset start (8), CRC (4), magic
    let summary_start = u64::from_le_bytes(std::array::from_fn(|i| tail[9 + i]));
    let has_footer = tail[0] == mcap::records::op::FOOTER && tail[29..] == mcap::MAGIC[..];
    if !has_footer {
        return Ok(Tail::Unfinished);
    }
    if summary_start >= footer {
        return Err(corrupt(
            path,
            format!(
                "not a complete MCAP file: its footer is damaged: the file is {len} bytes long \
                 and its footer (at byte {footer}) puts the summary at byte {summary_start}"
            ),
            "a footer that points back at the summary section before it (or 0: no summary)",
        ));
    }
    if summary_start == 0 {
        return Ok(Tail::NoSummary);
    }
    file.seek(SeekFrom::Start(0))
        .map_err(io_err(path, "seeking the summary"))?;
    // Given the file size, the reader asks for absolute positions only, within the file: the
    // footer's, then the summary's. (Without it, it seeks 37 bytes back from the end, which a
    // shorter file refuses with a bare OS error.)
    let options = SummaryReaderOptions::default()
        .with_file_size(len)
        .with_record_length_limit(RECORD_LENGTH_LIMIT);
    let mut reader = SummaryReader::new_with_options(options);
    let mut pos: u64 = 0;
    let unreadable = |error: String| Tail::Unreadable {
        footer,
        summary_start,
        error,
    };
    while let Some(event) = reader.next_event() {
        match event {
            Ok(SummaryReadEvent::ReadRequest(need)) => {
                let n = file
                    .read(reader.insert(read_size(need, pos, len)))
                    .map_err(io_err(path, "reading the summary"))?;
                pos += n as u64;
                reader.notify_read(n);
            }
            Ok(SummaryReadEvent::SeekRequest(to)) => {
                pos = file.seek(to).map_err(io_err(path, "seeking the summary"))?;
                reader.notify_seeked(pos);
            }
            Err(e) => return Ok(unreadable(e.to_string())),
        }
    }
    Ok(match reader.finish() {
        Some(summary) => Tail::Summary(Box::new(summary)),
        None => unreadable("no summary records there".to_owned()),
    })
}

/// The error for a file that ends before the header every railsim log starts with (the MCAP
/// magic and header and the `railsim_log` Metadata record, which [`crate::LogWriter::create`]
/// writes and flushes first): a log cut short at its very start, or not a railsim log.
fn too_short(path: &Path, len: u64, ends: &str) -> LogError {
    corrupt(
        path,
        format!("not a complete railsim log (MCAP file): the file is {len} bytes long and {ends}"),
        format!(
            "at least the MCAP magic, the MCAP header and the '{FORMAT_METADATA}' metadata \
             record that a railsim log starts with"
        ),
    )
}

/// Scans the file from the start, decompressing chunks one at a time, and hands every record to
/// `on_record`. With `finished`, any error is corruption; without it, running out of data stops
/// the scan cleanly (the end of a killed run) and is reported in [`ScanEnd::truncation`].
fn scan(
    path: &Path,
    finished: bool,
    mut on_record: impl FnMut(Record<'_>) -> Result<()>,
) -> Result<ScanEnd> {
    let mut file = File::open(path).map_err(io_err(path, "opening the log"))?;
    let len = file
        .metadata()
        .map_err(io_err(path, "reading the log"))?
        .len();
    let options = LinearReaderOptions::default()
        .with_skip_end_magic(!finished)
        // A chunk's messages are only handed out once the whole chunk is present and its CRC
        // checks: a chunk cut off by a crash contributes nothing rather than a partial tail.
        .with_prevalidate_chunk_crcs(true)
        .with_record_length_limit(RECORD_LENGTH_LIMIT);
    let mut reader = LinearReader::new_with_options(options);
    let mut consumed: u64 = 0;
    while let Some(event) = reader.next_event() {
        match event {
            Ok(LinearReadEvent::ReadRequest(need)) => {
                let n = file
                    .read(reader.insert(read_size(need, consumed, len)))
                    .map_err(io_err(path, "reading the log"))?;
                consumed += n as u64;
                reader.notify_read(n);
            }
            Ok(LinearReadEvent::Record { data, opcode }) => {
                let record = mcap::parse_record(opcode, data).map_err(|e| {
                    corrupt(
                        path,
                        format!("record with opcode 0x{opcode:02x} does not parse ({e})"),
                        "a well-formed MCAP record",
                    )
                })?;
                on_record(record)?;
            }
            Err(e) => {
                // (a record or chunk longer than the whole file ends inside it as well: its
                // length is refused by the limit before anything is read or allocated)
                let eof = match e {
                    mcap::McapError::UnexpectedEof | mcap::McapError::UnexpectedEoc => true,
                    mcap::McapError::RecordTooLarge { len: n, .. }
                    | mcap::McapError::ChunkTooLarge(n) => n > len,
                    _ => false,
                };
                if !finished && eof {
                    return Ok(ScanEnd {
                        truncation: Some(format!(
                            "the log ends inside a record after {consumed} bytes (the writer \
                             stopped before finishing); read up to the last complete chunk"
                        )),
                    });
                }
                return Err(corrupt(
                    path,
                    format!("reading records near byte {consumed}: {e}"),
                    "a complete MCAP data section",
                ));
            }
        }
    }
    Ok(ScanEnd {
        truncation: (!finished).then(|| {
            "the log has no summary (the writer stopped before finishing); \
             every complete chunk was read"
                .to_owned()
        }),
    })
}

impl LogReader {
    /// Opens the log at `path`: a finished one, or one whose writer was killed.
    ///
    /// An unfinished file must hold at least the header a railsim log starts with (MCAP magic,
    /// header and the `railsim_log` Metadata record, flushed when the log is created); a shorter
    /// one, and a finished one whose footer points beyond itself, is a [`LogError::Corrupt`]
    /// naming the file and its size.
    pub fn open(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        let mut file = File::open(&path).map_err(io_err(&path, "opening the log"))?;
        let len = file
            .metadata()
            .map_err(io_err(&path, "reading the log"))?
            .len();
        let mut magic = [0u8; 8];
        let mut got = 0;
        while got < magic.len() {
            let n = file
                .read(&mut magic[got..])
                .map_err(io_err(&path, "reading the log"))?;
            if n == 0 {
                break;
            }
            got += n;
        }
        if got < magic.len() && magic[..got] == mcap::MAGIC[..got] {
            let ends = if got == 0 { "before" } else { "inside" };
            return Err(too_short(
                &path,
                len,
                &format!("ends {ends} the 8 MCAP magic bytes"),
            ));
        }
        if magic[..got] != mcap::MAGIC[..] {
            return Err(corrupt(
                &path,
                format!("the file starts with {:02x?}", &magic[..got]),
                format!("the MCAP magic bytes {:02x?}", mcap::MAGIC),
            ));
        }
        let tail = read_summary(&path, &mut file, len)?;
        drop(file);
        // A finished file is scanned strictly (any error is corruption); one without a readable
        // summary like a killed run's, up to its last complete chunk.
        let finished = matches!(tail, Tail::Summary(_) | Tail::NoSummary);

        let mut schemas: HashMap<u16, (String, String, Vec<u8>)> = HashMap::new();
        let mut channels: Vec<ChannelInfo> = Vec::new();
        let mut by_id: HashMap<u16, usize> = HashMap::new();
        let mut metadata = BTreeMap::new();
        let mut attachments = Vec::new();
        let mut total: u64 = 0;
        let end = scan(&path, finished, |record| {
            match record {
                Record::Schema { header, data } => {
                    schemas
                        .entry(header.id)
                        .or_insert_with(|| (header.name, header.encoding, data.into_owned()));
                }
                Record::Channel(c) => {
                    if by_id.contains_key(&c.id) {
                        return Ok(());
                    }
                    let (schema_name, schema_encoding, schema) =
                        schemas.get(&c.schema_id).cloned().ok_or_else(|| {
                            corrupt(
                                &path,
                                format!(
                                    "channel '{}' refers to unknown schema {}",
                                    c.topic, c.schema_id
                                ),
                                "its schema record before the channel",
                            )
                        })?;
                    by_id.insert(c.id, channels.len());
                    channels.push(ChannelInfo {
                        id: c.id,
                        topic: c.topic,
                        schema_name,
                        schema_encoding,
                        schema,
                        message_encoding: c.message_encoding,
                        message_count: 0,
                        first_ns: None,
                        last_ns: None,
                    });
                }
                Record::Message { header, .. } => {
                    let Some(&index) = by_id.get(&header.channel_id) else {
                        return Err(corrupt(
                            &path,
                            format!("message on unknown channel {}", header.channel_id),
                            "its channel record before the message",
                        ));
                    };
                    let c = &mut channels[index];
                    c.message_count += 1;
                    let t = header.log_time;
                    c.first_ns = Some(c.first_ns.map_or(t, |f| f.min(t)));
                    c.last_ns = Some(c.last_ns.map_or(t, |l| l.max(t)));
                    total += 1;
                }
                Record::Metadata(m) => {
                    metadata.insert(m.name, m.metadata);
                }
                Record::Attachment { header, data, .. } => {
                    attachments.push((header.name, header.media_type, data.into_owned()));
                }
                _ => {}
            }
            Ok(())
        })?;

        // A finished MCAP file from another writer is read as it is; an unfinished one must at
        // least hold the header that railsim flushes when it creates a log.
        if !finished && !metadata.contains_key(FORMAT_METADATA) {
            return Err(too_short(
                &path,
                len,
                &format!("has no footer and no complete '{FORMAT_METADATA}' metadata record"),
            ));
        }
        // A log of a later format may mean other things by the same fields: refused, not misread.
        if let Some(v) = metadata
            .get(FORMAT_METADATA)
            .and_then(|m| m.get("format_version"))
            && !v.parse::<u32>().is_ok_and(|n| n <= FORMAT_VERSION)
        {
            return Err(LogError::Corrupt {
                path: path.clone(),
                what: format!("log format version \"{v}\" (metadata '{FORMAT_METADATA}')"),
                expected: format!(
                    "a format version up to {FORMAT_VERSION}, which this railsim reads (a \
                     log of a newer railsim)"
                ),
            });
        }
        let (summary, truncation) = match tail {
            Tail::Summary(summary) => (Some(*summary), end.truncation),
            Tail::NoSummary | Tail::Unfinished => (None, end.truncation),
            // (the scan ran as for a killed run; the footer says the file is whole, so the note
            // is about the footer)
            Tail::Unreadable {
                footer,
                summary_start,
                error,
            } => (
                None,
                Some(format!(
                    "its footer (at byte {footer}) is in place but puts the summary at byte \
                     {summary_start}, where no summary reads ({error}): the footer or the summary \
                     is damaged; the data section was read on its own, up to its last complete \
                     chunk"
                )),
            ),
        };
        if let Some(stats) = summary.as_ref().and_then(|s| s.stats.as_ref())
            && stats.message_count != total
        {
            return Err(corrupt(
                &path,
                format!("the data section holds {total} messages"),
                format!(
                    "{} messages, as the summary's statistics say",
                    stats.message_count
                ),
            ));
        }
        channels.sort_by(|a, b| a.topic.cmp(&b.topic));
        let by_id = channels
            .iter()
            .enumerate()
            .map(|(i, c)| (c.id, i))
            .collect();
        Ok(LogReader {
            path,
            summary,
            channels,
            by_id,
            metadata,
            attachments,
            finished,
            truncation,
        })
    }

    /// The log file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the log was finished: it has a footer and its summary reads, or the footer
    /// records no summary (allowed by MCAP; railsim's writer always writes one).
    pub fn is_complete(&self) -> bool {
        self.finished
    }

    /// For a log read without its summary, why and how: an unfinished log (the writer was
    /// killed), and how its readable part ends; or a footer in place whose summary does not read.
    pub fn truncation(&self) -> Option<&str> {
        self.truncation.as_deref()
    }

    /// The channels, sorted by topic.
    pub fn channels(&self) -> &[ChannelInfo] {
        &self.channels
    }

    /// The channel on `topic`, if any.
    pub fn channel(&self, topic: &str) -> Option<&ChannelInfo> {
        self.channels.iter().find(|c| c.topic == topic)
    }

    /// Total number of readable messages.
    pub fn message_count(&self) -> u64 {
        self.channels.iter().map(|c| c.message_count).sum()
    }

    /// \[ns\] The earliest and latest log times over all channels, if there are messages.
    pub fn time_range(&self) -> Option<(u64, u64)> {
        let first = self.channels.iter().filter_map(|c| c.first_ns).min()?;
        let last = self.channels.iter().filter_map(|c| c.last_ns).max()?;
        Some((first, last))
    }

    /// The scene's key/value pairs (Metadata record `scene`).
    pub fn scene(&self) -> Option<&BTreeMap<String, String>> {
        self.metadata.get(SCENE_METADATA)
    }

    /// All Metadata records by name.
    pub fn metadata(&self) -> &BTreeMap<String, BTreeMap<String, String>> {
        &self.metadata
    }

    /// The attachment `name` as `(media type, bytes)`.
    pub fn attachment(&self, name: &str) -> Option<(&str, &[u8])> {
        self.attachments
            .iter()
            .find(|(n, _, _)| n == name)
            .map(|(_, media, data)| (media.as_str(), data.as_slice()))
    }

    /// The scene TOML attached to the log, if any.
    pub fn scene_toml(&self) -> Result<Option<&str>> {
        match self.attachment(SCENE_ATTACHMENT) {
            None => Ok(None),
            Some((_, bytes)) => std::str::from_utf8(bytes).map(Some).map_err(|e| {
                corrupt(
                    &self.path,
                    format!("attachment '{SCENE_ATTACHMENT}' is not UTF-8 ({e})"),
                    "TOML text",
                )
            }),
        }
    }

    /// Calls `visit` for every message selected by `query`, in file order (which is log-time
    /// order for logs written by [`crate::LogWriter`]). A finished log is read through its chunk
    /// index, so only chunks overlapping the query are decompressed; an unfinished one is scanned.
    /// Memory is bounded by one chunk.
    pub fn for_each(
        &self,
        query: &Query,
        mut visit: impl FnMut(LogMessageRef<'_>) -> Result<()>,
    ) -> Result<()> {
        if let Some(topics) = &query.topics {
            for topic in topics {
                if self.channel(topic).is_none() {
                    return Err(LogError::Topic {
                        path: self.path.clone(),
                        message: format!("the log has no topic '{topic}'"),
                    });
                }
            }
        }
        let wanted: Option<BTreeSet<u16>> = query.topics.as_ref().map(|topics| {
            self.channels
                .iter()
                .filter(|c| topics.contains(&c.topic))
                .map(|c| c.id)
                .collect()
        });
        let accepts = |channel_id: u16, t: u64| {
            wanted.as_ref().is_none_or(|w| w.contains(&channel_id)) && query.accepts_time(t)
        };
        match &self.summary {
            Some(summary) => self.for_each_indexed(summary, query, accepts, &mut visit),
            None => {
                scan(&self.path, false, |record| {
                    if let Record::Message { header, data } = record
                        && accepts(header.channel_id, header.log_time)
                    {
                        visit(self.message_ref(&header, &data)?)?;
                    }
                    Ok(())
                })?;
                Ok(())
            }
        }
    }

    fn message_ref<'a>(
        &'a self,
        header: &mcap::records::MessageHeader,
        data: &'a [u8],
    ) -> Result<LogMessageRef<'a>> {
        let index = *self.by_id.get(&header.channel_id).ok_or_else(|| {
            corrupt(
                &self.path,
                format!("message on unknown channel {}", header.channel_id),
                "its channel record before the message",
            )
        })?;
        Ok(LogMessageRef {
            channel: &self.channels[index],
            sequence: header.sequence,
            log_time_ns: header.log_time,
            publish_time_ns: header.publish_time,
            data,
        })
    }

    fn for_each_indexed(
        &self,
        summary: &mcap::Summary,
        query: &Query,
        accepts: impl Fn(u16, u64) -> bool,
        visit: &mut impl FnMut(LogMessageRef<'_>) -> Result<()>,
    ) -> Result<()> {
        let mut options = IndexedReaderOptions::new()
            .with_order(mcap::sans_io::indexed_reader::ReadOrder::File)
            .with_record_length_limit(RECORD_LENGTH_LIMIT);
        if let Some(topics) = &query.topics {
            options = options.include_topics(topics.iter().cloned());
        }
        if let Some(start) = query.start_ns {
            options = options.starting_at(start);
        }
        if let Some(end) = query.end_ns {
            options = options.ending_at(end);
        }
        let index_err = |e: mcap::McapError| {
            corrupt(
                &self.path,
                format!("reading the indexed data: {e}"),
                "chunks matching the summary's chunk index",
            )
        };
        let mut reader = IndexedReader::new_with_options(summary, options).map_err(index_err)?;
        let mut file = File::open(&self.path).map_err(io_err(&self.path, "opening the log"))?;
        let file_len = file
            .metadata()
            .map_err(io_err(&self.path, "reading the log"))?
            .len();
        let mut buffer = Vec::new();
        while let Some(event) = reader.next_event() {
            match event.map_err(index_err)? {
                IndexedReadEvent::ReadChunkRequest { offset, length } => {
                    // a damaged index must not make the buffer larger than the file
                    if offset.saturating_add(length as u64) > file_len {
                        return Err(corrupt(
                            &self.path,
                            format!(
                                "the chunk index points at {length} bytes from offset {offset}, \
                                 beyond the end of the file ({file_len} bytes)"
                            ),
                            "chunks matching the summary's chunk index",
                        ));
                    }
                    file.seek(SeekFrom::Start(offset))
                        .map_err(io_err(&self.path, "seeking a chunk"))?;
                    buffer.resize(length, 0);
                    file.read_exact(&mut buffer)
                        .map_err(io_err(&self.path, "reading a chunk"))?;
                    reader
                        .insert_chunk_record_data(offset, &buffer)
                        .map_err(index_err)?;
                }
                IndexedReadEvent::Message { header, data } => {
                    if accepts(header.channel_id, header.log_time) {
                        visit(self.message_ref(&header, data)?)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// Calls `visit(log_time_ns, message)` for every message on `topic` (within the inclusive
    /// range `range_ns`, if given), decoded as `M`. The topic must exist and carry `M`'s schema.
    pub fn for_each_typed<M: LogMessage>(
        &self,
        topic: &str,
        range_ns: Option<(u64, u64)>,
        mut visit: impl FnMut(u64, M) -> Result<()>,
    ) -> Result<()> {
        let channel = self.channel(topic).ok_or_else(|| LogError::Topic {
            path: self.path.clone(),
            message: format!("the log has no topic '{topic}'"),
        })?;
        if channel.schema_name != M::SCHEMA_NAME {
            return Err(LogError::Topic {
                path: self.path.clone(),
                message: format!(
                    "topic '{topic}' carries {}, not {}",
                    channel.schema_name,
                    M::SCHEMA_NAME
                ),
            });
        }
        let mut query = Query::topics([topic]);
        if let Some((start, end)) = range_ns {
            query = query.between(start, end);
        }
        self.for_each(&query, |m| {
            let message: M = serde_json::from_slice(m.data).map_err(|source| LogError::Decode {
                path: self.path.clone(),
                topic: m.channel.topic.clone(),
                t_ns: m.log_time_ns,
                schema: M::SCHEMA_NAME,
                source,
            })?;
            visit(m.log_time_ns, message)
        })
    }

    /// All messages on `topic` (within `range_ns`, inclusive) as `(log_time_ns, message)`.
    /// This holds them all in memory; use [`LogReader::for_each_typed`] for long logs.
    pub fn read_topic<M: LogMessage>(
        &self,
        topic: &str,
        range_ns: Option<(u64, u64)>,
    ) -> Result<Vec<(u64, M)>> {
        let mut out = Vec::new();
        self.for_each_typed(topic, range_ns, |t, m| {
            out.push((t, m));
            Ok(())
        })?;
        Ok(out)
    }
}
