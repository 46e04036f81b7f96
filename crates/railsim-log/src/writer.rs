//! The streaming log writer.

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

use mcap::records::MessageHeader;
use mcap::write::NoSeek;

use crate::error::{LogError, Result};
use crate::messages::LogMessage;

/// Name of the Metadata record that holds the resolved scene as key/value pairs.
pub const SCENE_METADATA: &str = "scene";
/// Name of the attachment that holds the scene TOML, when one is given.
pub const SCENE_ATTACHMENT: &str = "scene.toml";
/// Name of the Metadata record that identifies the writer and format version.
pub const FORMAT_METADATA: &str = "railsim_log";
/// Version of the log layout and meaning described in `docs/formats/log.md`. 2 (stop 26): a
/// wheelset's `angular_velocity` includes its spin, and the positions are the vehicle file's
/// loaded geometry; 1 before.
pub const FORMAT_VERSION: u32 = 2;

/// What a log says about itself, written before any message.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LogHeader {
    /// The resolved scene as key/value pairs (Metadata record `scene`).
    pub scene: BTreeMap<String, String>,
    /// The scene as TOML text (attachment `scene.toml`, media type `application/toml`).
    pub scene_toml: Option<String>,
    /// Further Metadata records by name (must not be `scene` or `railsim_log`).
    pub extra_metadata: BTreeMap<String, BTreeMap<String, String>>,
}

impl LogHeader {
    /// An empty header.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one key/value pair to the scene metadata.
    pub fn scene_entry(mut self, key: impl Into<String>, value: impl Into<String>) -> Self {
        self.scene.insert(key.into(), value.into());
        self
    }

    /// Sets the scene TOML attached to the log.
    pub fn scene_toml(mut self, toml: impl Into<String>) -> Self {
        self.scene_toml = Some(toml.into());
        self
    }

    /// Adds a further Metadata record.
    pub fn metadata(mut self, name: impl Into<String>, entries: BTreeMap<String, String>) -> Self {
        self.extra_metadata.insert(name.into(), entries);
        self
    }
}

/// Options of a [`LogWriter`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WriterOptions {
    /// \[B\] target uncompressed chunk size; a chunk is closed when it grows past this size.
    /// This bounds the writer's memory: one chunk plus its compressed copy.
    pub chunk_size: u64,
    /// Flush (close the chunk and flush the file) after this many messages; 0 = only on
    /// demand and when a chunk fills.
    pub flush_every: u64,
    /// Compress chunks with zstd (default) or store them uncompressed.
    pub zstd: bool,
}

impl Default for WriterOptions {
    fn default() -> Self {
        WriterOptions {
            chunk_size: 256 * 1024,
            flush_every: 4096,
            zstd: true,
        }
    }
}

/// A typed handle of a registered channel, returned by [`LogWriter::channel`].
///
/// Writing through a handle avoids looking the topic up for every message.
#[derive(Debug)]
pub struct Channel<M> {
    index: usize,
    id: u16,
    _message: PhantomData<fn(&M)>,
}

impl<M> Clone for Channel<M> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<M> Copy for Channel<M> {}

#[derive(Debug)]
struct ChannelState {
    topic: String,
    schema_name: &'static str,
    id: u16,
    sequence: u32,
    messages: u64,
}

/// What [`LogWriter::finish`] reports.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogStats {
    /// The log file.
    pub path: PathBuf,
    /// Messages written.
    pub messages: u64,
    /// Messages per topic, in order of registration.
    pub per_topic: Vec<(String, u64)>,
    /// Chunks written.
    pub chunks: u32,
    /// Explicit and periodic flushes.
    pub flushes: u64,
    /// \[ns\] log time of the first message (0 with no messages)
    pub start_ns: u64,
    /// \[ns\] log time of the last message (0 with no messages)
    pub end_ns: u64,
    /// \[B\] size of the finished file
    pub bytes: u64,
}

type McapWriter = mcap::Writer<NoSeek<BufWriter<File>>>;

/// Writes a railsim log as a stream.
///
/// The file is created by [`LogWriter::create`], which writes the header metadata first.
/// Channels are registered with [`LogWriter::channel`] (or implicitly by
/// [`LogWriter::write_topic`]) and messages written with [`LogWriter::write`]. Log time and
/// publish time are both the given simulation time in integer nanoseconds; times must not
/// decrease from one message to the next.
///
/// Memory is bounded by one chunk (`chunk_size`, uncompressed, plus its compressed copy), the
/// reused serialisation buffer and the per-chunk message index: the writer never seeks, so a
/// chunk is assembled in memory and written whole.
///
/// Call [`LogWriter::finish`] at the end to write the summary and get the statistics. If the
/// writer is dropped without it (for example on an error path) the MCAP library still writes
/// the summary but any I/O error is lost; if the process dies, the file is readable up to the last
/// complete chunk (see [`LogWriter::flush`]).
pub struct LogWriter {
    path: PathBuf,
    mcap: McapWriter,
    options: WriterOptions,
    buf: Vec<u8>,
    channels: Vec<ChannelState>,
    by_topic: HashMap<String, usize>,
    schemas: HashMap<&'static str, u16>,
    first_ns: Option<u64>,
    last_ns: u64,
    messages: u64,
    since_flush: u64,
    flushes: u64,
}

impl std::fmt::Debug for LogWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LogWriter")
            .field("path", &self.path)
            .field("options", &self.options)
            .field("channels", &self.channels)
            .field("messages", &self.messages)
            .finish_non_exhaustive()
    }
}

impl LogWriter {
    /// Creates (or truncates) the log at `path` and writes the header: the MCAP header, the
    /// `railsim_log` and `scene` Metadata records, further metadata, and the scene TOML
    /// attachment, all before any chunk.
    pub fn create(
        path: impl AsRef<Path>,
        header: &LogHeader,
        options: WriterOptions,
    ) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        for name in header.extra_metadata.keys() {
            if name == SCENE_METADATA || name == FORMAT_METADATA {
                return Err(LogError::Topic {
                    path,
                    message: format!("extra metadata may not be named '{name}' (reserved)"),
                });
            }
        }
        let file = File::create(&path).map_err(|source| LogError::Io {
            path: path.clone(),
            action: "creating the log",
            source,
        })?;
        let chunk_size = options.chunk_size.max(1);
        let write_err = |source| LogError::Write {
            path: path.clone(),
            source,
        };
        let mut mcap = mcap::WriteOptions::new()
            .compression(options.zstd.then_some(mcap::Compression::Zstd))
            .chunk_size(Some(chunk_size))
            .disable_seeking(true)
            // Single-threaded compression: the simulator owns the cores, and the output bytes
            // are then the same on every machine.
            .compression_threads(0)
            .library(format!("railsim-log/{}", env!("CARGO_PKG_VERSION")))
            .profile("")
            .create(NoSeek::new(BufWriter::new(file)))
            .map_err(write_err)?;

        let format: BTreeMap<String, String> = [
            ("format_version".to_owned(), FORMAT_VERSION.to_string()),
            (
                "writer".to_owned(),
                format!("railsim-log {}", env!("CARGO_PKG_VERSION")),
            ),
            (
                "time".to_owned(),
                "log_time = publish_time = simulation time in ns".to_owned(),
            ),
        ]
        .into();
        mcap.write_metadata(&mcap::records::Metadata {
            name: FORMAT_METADATA.to_owned(),
            metadata: format,
        })
        .map_err(write_err)?;
        mcap.write_metadata(&mcap::records::Metadata {
            name: SCENE_METADATA.to_owned(),
            metadata: header.scene.clone(),
        })
        .map_err(write_err)?;
        for (name, entries) in &header.extra_metadata {
            mcap.write_metadata(&mcap::records::Metadata {
                name: name.clone(),
                metadata: entries.clone(),
            })
            .map_err(write_err)?;
        }
        if let Some(toml) = &header.scene_toml {
            mcap.attach(&mcap::Attachment {
                log_time: 0,
                create_time: 0,
                name: SCENE_ATTACHMENT.to_owned(),
                media_type: "application/toml".to_owned(),
                data: Cow::Borrowed(toml.as_bytes()),
            })
            .map_err(write_err)?;
        }
        // Make the header durable at once: a run killed before its first flush still leaves a
        // log that names its scene.
        mcap.flush().map_err(write_err)?;

        Ok(LogWriter {
            path,
            mcap,
            options,
            buf: Vec::with_capacity(1024),
            channels: Vec::new(),
            by_topic: HashMap::new(),
            schemas: HashMap::new(),
            first_ns: None,
            last_ns: 0,
            messages: 0,
            since_flush: 0,
            flushes: 0,
        })
    }

    /// The log file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Messages written so far.
    pub fn message_count(&self) -> u64 {
        self.messages
    }

    fn write_err(&self, source: mcap::McapError) -> LogError {
        LogError::Write {
            path: self.path.clone(),
            source,
        }
    }

    /// Registers `topic` for messages of type `M` (schema and channel records) and returns its
    /// handle. Registering a topic again returns the same channel; registering it with another
    /// message type is an error.
    pub fn channel<M: LogMessage>(&mut self, topic: &str) -> Result<Channel<M>> {
        if let Some(&index) = self.by_topic.get(topic) {
            return self.handle_for::<M>(index);
        }
        let schema_id = match self.schemas.get(M::SCHEMA_NAME) {
            Some(&id) => id,
            None => {
                let id = self
                    .mcap
                    .add_schema(M::SCHEMA_NAME, "jsonschema", &M::schema_json())
                    .map_err(|e| self.write_err(e))?;
                self.schemas.insert(M::SCHEMA_NAME, id);
                id
            }
        };
        let id = self
            .mcap
            .add_channel(schema_id, topic, "json", &BTreeMap::new())
            .map_err(|e| self.write_err(e))?;
        let index = self.channels.len();
        self.channels.push(ChannelState {
            topic: topic.to_owned(),
            schema_name: M::SCHEMA_NAME,
            id,
            sequence: 0,
            messages: 0,
        });
        self.by_topic.insert(topic.to_owned(), index);
        Ok(Channel {
            index,
            id,
            _message: PhantomData,
        })
    }

    fn handle_for<M: LogMessage>(&self, index: usize) -> Result<Channel<M>> {
        let state = &self.channels[index];
        if state.schema_name != M::SCHEMA_NAME {
            return Err(LogError::Topic {
                path: self.path.clone(),
                message: format!(
                    "topic '{}' carries {}, not {}",
                    state.topic,
                    state.schema_name,
                    M::SCHEMA_NAME
                ),
            });
        }
        Ok(Channel {
            index,
            id: state.id,
            _message: PhantomData,
        })
    }

    /// Writes `message` on the channel `channel` at simulation time `t_ns` (log time = publish
    /// time = `t_ns`). Derive `t_ns` from an integer step counter ([`crate::step_time_ns`]).
    pub fn write<M: LogMessage>(
        &mut self,
        channel: &Channel<M>,
        t_ns: u64,
        message: &M,
    ) -> Result<()> {
        let Some(state) = self
            .channels
            .get(channel.index)
            .filter(|s| s.id == channel.id)
        else {
            return Err(LogError::Topic {
                path: self.path.clone(),
                message: format!("channel handle {} does not belong to this log", channel.id),
            });
        };
        if t_ns < self.last_ns {
            return Err(LogError::TimeWentBackwards {
                path: self.path.clone(),
                topic: state.topic.clone(),
                t_ns,
                previous_ns: self.last_ns,
            });
        }
        self.buf.clear();
        if let Err(source) = serde_json::to_writer(&mut self.buf, message) {
            return Err(LogError::Decode {
                path: self.path.clone(),
                topic: state.topic.clone(),
                t_ns,
                schema: M::SCHEMA_NAME,
                source,
            });
        }
        let header = MessageHeader {
            channel_id: channel.id,
            sequence: state.sequence,
            log_time: t_ns,
            publish_time: t_ns,
        };
        if let Err(e) = self.mcap.write_to_known_channel(&header, &self.buf) {
            return Err(self.write_err(e));
        }
        let state = &mut self.channels[channel.index];
        state.sequence = state.sequence.wrapping_add(1);
        state.messages += 1;
        self.first_ns.get_or_insert(t_ns);
        self.last_ns = t_ns;
        self.messages += 1;
        self.since_flush += 1;
        if self.options.flush_every > 0 && self.since_flush >= self.options.flush_every {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes `message` on `topic`, registering the topic on first use. Looks the topic up by
    /// name on every call; prefer [`LogWriter::channel`] + [`LogWriter::write`] in a loop.
    pub fn write_topic<M: LogMessage>(
        &mut self,
        topic: &str,
        t_ns: u64,
        message: &M,
    ) -> Result<()> {
        let channel = self.channel::<M>(topic)?;
        self.write(&channel, t_ns, message)
    }

    /// Writes a further Metadata record now (e.g. results known only at the end of a run). The
    /// reserved names `scene` and `railsim_log` are refused.
    pub fn write_metadata(&mut self, name: &str, entries: BTreeMap<String, String>) -> Result<()> {
        if name == SCENE_METADATA || name == FORMAT_METADATA {
            return Err(LogError::Topic {
                path: self.path.clone(),
                message: format!("metadata may not be named '{name}' (reserved)"),
            });
        }
        self.mcap
            .write_metadata(&mcap::records::Metadata {
                name: name.to_owned(),
                metadata: entries,
            })
            .map_err(|e| self.write_err(e))
    }

    /// Closes the current chunk and flushes the file buffer to the operating system. After it
    /// returns, every message written so far survives the process being killed. (It does not
    /// `fsync`: a power loss may still lose data the OS had not written.)
    pub fn flush(&mut self) -> Result<()> {
        self.mcap.flush().map_err(|e| self.write_err(e))?;
        self.since_flush = 0;
        self.flushes += 1;
        Ok(())
    }

    /// Writes the summary (schemas, channels, statistics, chunk/metadata/attachment indexes) and
    /// the footer, flushes the file and reports statistics.
    pub fn finish(mut self) -> Result<LogStats> {
        let summary = self.mcap.finish().map_err(|e| self.write_err(e))?;
        let mut out = self.mcap.into_inner().into_inner();
        out.flush().map_err(|source| LogError::Io {
            path: self.path.clone(),
            action: "flushing the log",
            source,
        })?;
        let bytes = out
            .get_ref()
            .metadata()
            .map(|m| m.len())
            .map_err(|source| LogError::Io {
                path: self.path.clone(),
                action: "reading the log's size",
                source,
            })?;
        Ok(LogStats {
            path: self.path,
            messages: self.messages,
            per_topic: self
                .channels
                .into_iter()
                .map(|c| (c.topic, c.messages))
                .collect(),
            chunks: summary.stats.as_ref().map_or(0, |s| s.chunk_count),
            flushes: self.flushes,
            start_ns: self.first_ns.unwrap_or(0),
            end_ns: self.last_ns,
            bytes,
        })
    }
}
